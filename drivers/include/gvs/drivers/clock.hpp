// Monotonic time in nanoseconds and absolute sleeps: the clock of frame
// times and of gvsd's real-time threads.
#pragma once

#include <atomic>
#include <cerrno>
#include <cstdint>
#include <ctime>

namespace gvs::drivers {

inline constexpr std::int64_t kNsPerMs = 1'000'000;
inline constexpr std::int64_t kNsPerS = 1'000'000'000;

inline std::int64_t to_ns(const timespec& ts) noexcept {
  return static_cast<std::int64_t>(ts.tv_sec) * kNsPerS + ts.tv_nsec;
}
inline timespec to_timespec(std::int64_t ns) noexcept {
  timespec ts{};
  ts.tv_sec = static_cast<time_t>(ns / kNsPerS);
  ts.tv_nsec = static_cast<long>(ns % kNsPerS);
  return ts;
}

/// CLOCK_MONOTONIC now, in nanoseconds.
inline std::int64_t mono_now_ns() noexcept {
  timespec ts{};
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return to_ns(ts);
}
/// CLOCK_REALTIME now, in nanoseconds since the epoch.
inline std::int64_t real_now_ns() noexcept {
  timespec ts{};
  clock_gettime(CLOCK_REALTIME, &ts);
  return to_ns(ts);
}

/// Sleeps until the absolute CLOCK_MONOTONIC time `t_ns`
/// (clock_nanosleep with TIMER_ABSTIME, restarted after signals).
inline void sleep_until_ns(std::int64_t t_ns) noexcept {
  const timespec ts = to_timespec(t_ns);
  while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, nullptr) == EINTR) {
  }
}

/// Sleeps until monotonic `t_ns` in short steps; false if `stop` was raised.
inline bool sleep_until_or_stop(std::int64_t t_ns, const std::atomic<bool>& stop) noexcept {
  constexpr std::int64_t kChunkNs = 50 * kNsPerMs;  // notice a stop request within 50 ms
  for (;;) {
    if (stop.load(std::memory_order_relaxed)) return false;
    const std::int64_t now = mono_now_ns();
    if (now >= t_ns) return true;
    sleep_until_ns(t_ns - now > kChunkNs ? now + kChunkNs : t_ns);
  }
}

}  // namespace gvs::drivers
