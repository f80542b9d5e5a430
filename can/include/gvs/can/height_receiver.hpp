// The camera's height from an external distance sensor on CAN: its frames
// received on a SocketCAN interface with their kernel receive time, kept as
// a short history, and read at a frame's mid-exposure instant.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>

#include "gvs/can/foreign_signal.hpp"

namespace gvs::can {

/// The newest height samples on the monotonic clock (pure state, no I/O).
class HeightHistory {
 public:
  /// Keeps the sample; one older than the newest, or not finite, or not
  /// above 0, is ignored (returns false).
  bool add(std::int64_t t_ns, double height_mm) noexcept;

  /// The height at `t_ns`: interpolated linearly between the samples on
  /// either side when they are at most `max_gap_ns` apart; the newest sample
  /// when `t_ns` follows it by at most `max_gap_ns`; nothing otherwise (no
  /// sample near enough: the scale stays uncorrected, never guessed).
  [[nodiscard]] std::optional<double> at(std::int64_t t_ns, std::int64_t max_gap_ns) const noexcept;

  [[nodiscard]] std::size_t size() const noexcept { return count_; }
  /// Samples kept since construction (the health line's count).
  [[nodiscard]] std::uint64_t kept() const noexcept { return kept_; }

 private:
  struct Sample {
    std::int64_t t_ns = 0;
    double height_mm = 0.0;
  };
  static constexpr std::size_t kCapacity = 64;  ///< 64 ms at a 1 kHz sensor
  [[nodiscard]] const Sample& nth_newest(std::size_t n) const noexcept {
    return samples_[(next_ + kCapacity - 1 - n) % kCapacity];
  }
  std::array<Sample, kCapacity> samples_{};
  std::size_t next_ = 0;
  std::size_t count_ = 0;
  std::uint64_t kept_ = 0;
};

/// A CAN_RAW socket on `iface` that receives only the signal's message.
class HeightReceiver {
 public:
  /// Throws std::runtime_error naming the interface and what to do when it
  /// cannot be opened, std::invalid_argument for a bad signal.
  HeightReceiver(std::string iface, ForeignSignal signal);
  ~HeightReceiver();
  HeightReceiver(const HeightReceiver&) = delete;
  HeightReceiver& operator=(const HeightReceiver&) = delete;

  /// Reads every frame waiting (without blocking) into `history`, each at
  /// its kernel receive time moved onto CLOCK_MONOTONIC. Returns the samples
  /// added. Never throws, never allocates.
  std::size_t drain(HeightHistory& history) noexcept;

  [[nodiscard]] std::uint64_t frames() const noexcept { return frames_; }
  [[nodiscard]] std::uint64_t read_errors() const noexcept { return read_errors_; }
  [[nodiscard]] const std::string& interface_name() const noexcept { return iface_; }

 private:
  std::string iface_;
  ForeignSignal signal_;
  int fd_ = -1;
  std::uint64_t frames_ = 0;
  std::uint64_t read_errors_ = 0;
};

}  // namespace gvs::can
