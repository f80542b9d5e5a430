// Fresh data on the bus: the CAN sender's slots moved to just after the
// estimates are published ([can] align_to_frames). Without it an estimate
// waits for the next fixed slot, 0 to one period (20 ms) at random; with
// it, the wait is the processing time of recent frames plus a margin.
//
// The camera runs at a rate that divides or is a multiple of the CAN rate
// (50 Hz CAN: 25, 50, 100 or 250 fps), so the frames' capture times keep one
// phase modulo Q = min(frame period, CAN period). The slot that should
// carry a frame's estimate is at
//     capture phase + budget + margin      (modulo Q),
// capture phase = the median phase of the last 8 capture times (a frame
// that reaches gvsd late, a cold first render or a late wake-up, moves
// neither the phase nor the slots; a camera whose phase moves for good
// moves it within 5 frames), budget = the second longest capture-to-publish
// time of the last 64 estimates: one slow frame (a preemption, a page
// fault) does not move the slots, two do; a frame slower than the budget
// goes out in a later slot. The third estimate moves the slots there in
// one step (only later, never into the past); after that they slew at most
// `slew_ns` per period, so the ECU sees every period within that of
// nominal while the lock follows the camera's clock and the estimator's time.
//
// Pure: no clocks, no I/O, no allocation, no exceptions after construction;
// time comes from the arguments (PX4's OpticalFlowAccumulator is the model).
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>

namespace gvs::daemon {

/// Why [can] align_to_frames cannot work with these rates ("" when it can),
/// naming the keys and what to do.
[[nodiscard]] std::string slot_alignment_refusal(int period_ms, double frame_rate_fps);

class SlotPhaseLock {
 public:
  /// Q for a CAN period and a frame rate: the frame period when the camera
  /// delivers a whole number of frames per CAN period, the CAN period when
  /// a whole number of CAN periods pass per frame, none otherwise (1 % slack).
  [[nodiscard]] static std::optional<std::int64_t> modulus_ns(std::int64_t can_period_ns, double frame_rate_fps) noexcept;

  /// Throws std::invalid_argument when the rates do not lock (modulus_ns empty).
  SlotPhaseLock(std::int64_t can_period_ns, double frame_rate_fps, std::int64_t margin_ns = 1'000'000,
                std::int64_t slew_ns = 100'000);

  /// A newly published estimate: when its frame was captured and when it was published.
  void on_estimate(std::int64_t captured_ns, std::int64_t published_ns) noexcept;
  /// The sender's next wake time, moved toward the lock.
  [[nodiscard]] std::int64_t adjust(std::int64_t next_ns) noexcept;

  [[nodiscard]] bool locked() const noexcept { return locked_; }
  [[nodiscard]] std::int64_t modulus_ns() const noexcept { return modulus_ns_; }
  /// The second longest capture-to-publish time of the last 64 estimates
  /// (the longest while there is only one).
  [[nodiscard]] std::int64_t budget_ns() const noexcept;
  /// The newest capture time moved to the median phase (modulo Q) of the
  /// last kPhaseHistory capture times.
  [[nodiscard]] std::int64_t capture_phase_ns() const noexcept;
  /// Estimates seen before the first step.
  static constexpr std::size_t kLockAfter = 3;

 private:
  static constexpr std::size_t kHistory = 64;
  static constexpr std::size_t kPhaseHistory = 8;
  std::int64_t modulus_ns_;
  std::int64_t margin_ns_;
  std::int64_t slew_ns_;
  std::array<std::int64_t, kHistory> publish_delay_ns_{};
  std::array<std::int64_t, kPhaseHistory> captured_ns_{};
  std::size_t delays_ = 0;  ///< estimates seen (the history holds the last kHistory)
  std::int64_t last_captured_ns_ = 0;
  bool locked_ = false;
};

}  // namespace gvs::daemon
