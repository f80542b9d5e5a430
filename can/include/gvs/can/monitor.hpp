// Decoding and statistics of gvs traffic for `gvs monitor`: last values,
// message rates, CRC errors, alive-counter jumps, bus error frames. Takes
// arbitrary frames and timestamps (from a bus or a log); never throws on
// input, so it can be fuzzed.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>

#include "gvs/can/codec.hpp"
#include "gvs/can/frame.hpp"

namespace gvs::can {

struct MessageStats {
  std::uint64_t frames = 0;          ///< frames with this ID (any content)
  std::uint64_t crc_errors = 0;
  std::uint64_t bad_length = 0;
  std::uint64_t counter_jumps = 0;   ///< alive counter moved by anything but +1
  std::uint64_t counter_repeats = 0; ///< alive counter did not move (delta 0)
  std::uint64_t frames_lost = 0;     ///< sum of (delta - 1) over forward jumps
  std::int64_t first_t_ns = 0;
  std::int64_t last_t_ns = 0;
  double max_gap_ms = 0.0;           ///< longest time between two frames

  /// Frames per second over the recent window (0 until two frames arrived).
  [[nodiscard]] double recent_rate_hz() const noexcept;
  /// Frames per second over the whole run.
  [[nodiscard]] double mean_rate_hz() const noexcept;

  // internal state
  bool have_counter = false;
  std::uint8_t last_counter = 0;
  static constexpr std::size_t kWindow = 32;
  std::array<std::int64_t, kWindow> recent_t_ns{};
  std::size_t recent_count = 0;  ///< stored timestamps (<= kWindow)
  std::size_t recent_next = 0;
};

struct BusErrorStats {
  std::uint64_t error_frames = 0;
  std::uint64_t bus_off = 0;
  std::uint64_t error_passive = 0;
  std::uint64_t controller_problems = 0;
  std::uint64_t restarts = 0;
};

/// The word of a GVS_Method code, or nullptr for a code it does not know.
/// The codes belong to the estimator's vocabulary, which the CAN library
/// does not include: the program that shows the monitor passes its table.
using MethodWordFn = const char* (*)(std::uint8_t code) noexcept;

class MonitorState {
 public:
  /// Without `method_word`, GVS_Method is shown as its number only.
  explicit MonitorState(MessageIds ids = {}, MethodWordFn method_word = nullptr)
      : ids_(ids), method_word_(method_word) {}

  /// One frame received at `t_ns` (any clock, only differences matter).
  void feed(const CanFrame& frame, std::int64_t t_ns) noexcept;
  /// A log line that could not be parsed.
  void note_malformed_line() noexcept { ++malformed_lines_; }

  [[nodiscard]] const MessageStats& stats(MessageKind kind) const noexcept {
    return stats_[static_cast<std::size_t>(kind)];
  }
  [[nodiscard]] const BusErrorStats& bus_errors() const noexcept { return bus_errors_; }
  [[nodiscard]] std::uint64_t total_frames() const noexcept { return total_frames_; }
  [[nodiscard]] std::uint64_t other_frames() const noexcept { return other_frames_; }
  [[nodiscard]] std::uint64_t malformed_lines() const noexcept { return malformed_lines_; }

  /// Last CRC-correct content of each message (and whether any arrived).
  [[nodiscard]] bool has(MessageKind kind) const noexcept { return has_[static_cast<std::size_t>(kind)]; }
  [[nodiscard]] const VelocityMsg& velocity() const noexcept { return velocity_; }
  [[nodiscard]] const VelocityXyMsg& velocity_xy() const noexcept { return xy_; }
  [[nodiscard]] const StatusMsg& status() const noexcept { return status_; }
  [[nodiscard]] const TimingMsg& timing() const noexcept { return timing_; }
  [[nodiscard]] const RideHeightMsg& ride_height() const noexcept { return ride_; }
  [[nodiscard]] std::int64_t last_t_ns() const noexcept { return last_t_ns_; }

  /// Nothing at all for longer than this: the view says so on top.
  static constexpr double kSilentAfterMs = 100.0;
  /// No frame of `kind` for three of its mean periods (at least
  /// kSilentAfterMs) before `now_ns`: its last values are no longer current.
  [[nodiscard]] bool silent(MessageKind kind, std::int64_t now_ns) const noexcept;

  /// The terminal view: values, validity, age, rates, counters, errors.
  /// `now_ns` (same clock as feed) gives the time since each message; a
  /// silent message shows rate 0 and validity "old", never "yes".
  [[nodiscard]] std::string render(std::int64_t now_ns) const;

 private:
  MessageIds ids_;
  MethodWordFn method_word_ = nullptr;
  std::array<MessageStats, kMessageKindCount> stats_{};
  std::array<bool, kMessageKindCount> has_{};
  BusErrorStats bus_errors_;
  VelocityMsg velocity_;
  VelocityXyMsg xy_;
  StatusMsg status_;
  TimingMsg timing_;
  RideHeightMsg ride_;
  std::uint64_t total_frames_ = 0;
  std::uint64_t other_frames_ = 0;
  std::uint64_t malformed_lines_ = 0;
  std::int64_t last_t_ns_ = 0;
};

}  // namespace gvs::can
