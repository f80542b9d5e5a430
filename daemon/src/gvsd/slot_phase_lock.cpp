#include "gvs/daemon/slot_phase_lock.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>

namespace gvs::daemon {

namespace {

/// `x` modulo `m` in [0, m).
std::int64_t wrap(std::int64_t x, std::int64_t m) noexcept {
  const std::int64_t r = x % m;
  return r < 0 ? r + m : r;
}

/// The whole number `r` is close to (within 1 %), or 0.
std::int64_t whole(double r) noexcept {
  const double n = std::round(r);
  return n >= 1.0 && std::fabs(r - n) <= 0.01 * n ? static_cast<std::int64_t>(n) : 0;
}

}  // namespace

std::optional<std::int64_t> SlotPhaseLock::modulus_ns(std::int64_t can_period_ns, double frame_rate_fps) noexcept {
  if (can_period_ns <= 0 || !(frame_rate_fps > 0.0)) return std::nullopt;
  const double frames_per_period = static_cast<double>(can_period_ns) * 1e-9 * frame_rate_fps;
  if (const std::int64_t m = whole(frames_per_period); m > 0) return can_period_ns / m;
  if (whole(1.0 / frames_per_period) > 0) return can_period_ns;
  return std::nullopt;
}

std::string slot_alignment_refusal(int period_ms, double frame_rate_fps) {
  if (SlotPhaseLock::modulus_ns(static_cast<std::int64_t>(period_ms) * 1'000'000, frame_rate_fps)) return {};
  char text[320];
  std::snprintf(text, sizeof text,
                "[can] align_to_frames: the frame rate %g fps is neither a multiple nor a divisor of the CAN rate "
                "%g Hz ([can] period_ms = %d); set the camera's frame rate to one that is (%g, %g or %g fps), or "
                "align_to_frames = false",
                frame_rate_fps, 1000.0 / period_ms, period_ms, 1000.0 / period_ms / 2.0, 1000.0 / period_ms,
                2000.0 / period_ms);
  return text;
}

SlotPhaseLock::SlotPhaseLock(std::int64_t can_period_ns, double frame_rate_fps, std::int64_t margin_ns,
                             std::int64_t slew_ns)
    : margin_ns_(margin_ns), slew_ns_(slew_ns) {
  const std::optional<std::int64_t> q = modulus_ns(can_period_ns, frame_rate_fps);
  if (!q) {
    char text[160];
    std::snprintf(text, sizeof text, "the frame rate %g fps is neither a multiple nor a divisor of the CAN rate %g Hz",
                  frame_rate_fps, 1e9 / static_cast<double>(can_period_ns));
    throw std::invalid_argument(text);
  }
  modulus_ns_ = *q;
}

void SlotPhaseLock::on_estimate(std::int64_t captured_ns, std::int64_t published_ns) noexcept {
  publish_delay_ns_[delays_ % kHistory] = std::max<std::int64_t>(0, published_ns - captured_ns);
  captured_ns_[delays_ % kPhaseHistory] = captured_ns;
  ++delays_;
  last_captured_ns_ = captured_ns;
}

std::int64_t SlotPhaseLock::budget_ns() const noexcept {
  const std::size_t n = std::min(delays_, kHistory);
  std::int64_t longest = 0, second = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const std::int64_t d = publish_delay_ns_[i];
    if (d > longest) {
      second = longest;
      longest = d;
    } else if (d > second) {
      second = d;
    }
  }
  return n == 1 ? longest : second;
}

std::int64_t SlotPhaseLock::capture_phase_ns() const noexcept {
  // Each capture's phase against the newest one's, in [-Q/2, Q/2): a frame
  // that arrived late shows as a positive offset, and the median ignores it.
  const std::size_t n = std::min(delays_, kPhaseHistory);
  if (n == 0) return last_captured_ns_;
  std::array<std::int64_t, kPhaseHistory> offsets{};
  for (std::size_t i = 0; i < n; ++i)
    offsets[i] = wrap(captured_ns_[i] - last_captured_ns_ + modulus_ns_ / 2, modulus_ns_) - modulus_ns_ / 2;
  const auto mid = offsets.begin() + static_cast<std::ptrdiff_t>(n / 2);
  std::nth_element(offsets.begin(), mid, offsets.begin() + static_cast<std::ptrdiff_t>(n));
  return last_captured_ns_ + *mid;
}

std::int64_t SlotPhaseLock::adjust(std::int64_t next_ns) noexcept {
  if (delays_ < kLockAfter) return next_ns;
  const std::int64_t target = capture_phase_ns() + budget_ns() + margin_ns_;
  // How far the slot is behind the target's phase, in [0, Q): moving it
  // later by that much puts it on the target; earlier by Q minus that too.
  const std::int64_t later = wrap(target - next_ns, modulus_ns_);
  if (!locked_) {
    locked_ = true;
    return next_ns + later;  // one step, forward only: never into the past
  }
  const std::int64_t step = later <= modulus_ns_ / 2 ? later : later - modulus_ns_;
  return next_ns + std::clamp(step, -slew_ns_, slew_ns_);
}

}  // namespace gvs::daemon
