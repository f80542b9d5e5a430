// Single-writer sequence lock for a small trivially copyable value.
//
// The writer never waits; readers retry while a write is in progress. The
// payload is kept in acquire/release atomic words (no plain
// data race, no standalone fences), so the pattern is correct under the C++
// memory model and clean under ThreadSanitizer (H.-J. Boehm, "Can seqlocks
// get along with programming language memory models?", MSPC 2012).
#pragma once

#include <array>
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <type_traits>

namespace gvs::daemon {

template <typename T>
class Seqlock {
  static_assert(std::is_trivially_copyable_v<T>, "Seqlock holds trivially copyable values");

 public:
  Seqlock() { store(T{}); version_.store(0, std::memory_order_relaxed); }
  explicit Seqlock(const T& initial) { store(initial); version_.store(0, std::memory_order_relaxed); }
  Seqlock(const Seqlock&) = delete;
  Seqlock& operator=(const Seqlock&) = delete;

  /// Writer (one thread only): replaces the value.
  void write(const T& value) noexcept {
    const std::uint64_t seq = seq_.load(std::memory_order_relaxed);
    seq_.store(seq + 1, std::memory_order_relaxed);  // odd: write in progress
    store(value);  // release stores: a reader that sees any new word also sees the odd seq
    seq_.store(seq + 2, std::memory_order_release);
    version_.store(seq / 2 + 1, std::memory_order_release);
  }

  /// Reader (any thread): a consistent copy of the latest value.
  [[nodiscard]] T read() const noexcept {
    std::array<std::uint64_t, kWords> buf{};
    for (;;) {
      const std::uint64_t before = seq_.load(std::memory_order_acquire);
      if ((before & 1U) != 0U) continue;
      for (std::size_t i = 0; i < kWords; ++i) buf[i] = words_[i].load(std::memory_order_acquire);
      if (seq_.load(std::memory_order_relaxed) == before) break;
    }
    T out;
    std::memcpy(static_cast<void*>(&out), buf.data(), sizeof(T));
    return out;
  }

  /// Number of completed writes (0: never written). Cheap change detection.
  [[nodiscard]] std::uint64_t version() const noexcept {
    return version_.load(std::memory_order_acquire);
  }

 private:
  static constexpr std::size_t kWords = (sizeof(T) + sizeof(std::uint64_t) - 1) / sizeof(std::uint64_t);

  void store(const T& value) noexcept {
    std::array<std::uint64_t, kWords> buf{};
    std::memcpy(buf.data(), &value, sizeof(T));
    for (std::size_t i = 0; i < kWords; ++i) words_[i].store(buf[i], std::memory_order_release);
  }

  alignas(64) std::atomic<std::uint64_t> seq_{0};
  std::atomic<std::uint64_t> version_{0};
  std::array<std::atomic<std::uint64_t>, kWords> words_{};
};

}  // namespace gvs::daemon
