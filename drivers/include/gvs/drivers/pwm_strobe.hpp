// LED strobe on a PWM output through the Linux PWM sysfs interface
// (Documentation/ABI/testing/sysfs-class-pwm): the pulse is hardware-timed.
//
//   <root>/pwmchipN/export          write M to create pwmM
//   <root>/pwmchipN/pwmM/period     ns
//   <root>/pwmchipN/pwmM/duty_cycle ns (<= period)
//   <root>/pwmchipN/pwmM/polarity   normal | inversed (only while disabled)
//   <root>/pwmchipN/pwmM/enable     0 | 1
//
// period = frame period, duty = the plan's pulse (or the whole exposure when
// it has no pulses). One pulse per period only: a double pulse needs a
// second pulse inside one frame, which the PWM ABI cannot express (it needs
// a burst/one-pulse timer or the camera's own strobe output), so arm()
// refuses plans with more than one pulse.
#pragma once

#include <string>

#include "gvs/drivers/strobe.hpp"

namespace gvs::drivers {

class PwmStrobe final : public StrobeDriver {
 public:
  /// Exports the channel if needed, disables it, sets polarity (active_low →
  /// inversed) and opens period/duty_cycle/enable for writing. Throws
  /// std::runtime_error naming the path and what to do.
  explicit PwmStrobe(const StrobeConfig& config);
  ~PwmStrobe() override;

  [[nodiscard]] std::string describe() const override;
  bool arm(const core::ExposurePlan& plan, double frame_period_us) noexcept override;
  FireReport fire(std::int64_t) noexcept override { return {}; }
  [[nodiscard]] std::span<const StrobeEdge> last_edges() const noexcept override { return {}; }
  [[nodiscard]] bool hardware_timed() const noexcept override { return true; }

  [[nodiscard]] std::int64_t period_ns() const noexcept { return period_ns_; }
  [[nodiscard]] std::int64_t duty_ns() const noexcept { return duty_ns_; }

 private:
  std::string channel_dir_;
  std::string period_path_, duty_path_, enable_path_;  ///< built at set-up: arm() only opens and writes
  std::int64_t period_ns_ = 0;  ///< as last written (0: not yet)
  std::int64_t duty_ns_ = 0;
  bool enabled_ = false;
};

}  // namespace gvs::drivers
