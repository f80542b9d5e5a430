// LED ring and trigger on GPIO lines (libgpiod 1.6), timed from user space.
#pragma once

#include "gvs/drivers/strobe.hpp"

struct gpiod_chip;
struct gpiod_line;

namespace gvs::drivers {

class GpioStrobe final : public StrobeDriver {
 public:
  /// Opens the chip and requests the lines as outputs, off. Throws
  /// std::runtime_error naming the chip/line and what to do.
  explicit GpioStrobe(const StrobeConfig& config);
  ~GpioStrobe() override;

  [[nodiscard]] std::string describe() const override;
  bool arm(const core::ExposurePlan& plan, double frame_period_us) noexcept override;
  FireReport fire(std::int64_t start_ns) noexcept override;
  [[nodiscard]] std::span<const StrobeEdge> last_edges() const noexcept override {
    return {schedule_.edges.data(), schedule_.count};
  }
  [[nodiscard]] bool hardware_timed() const noexcept override { return false; }

 private:
  StrobeConfig config_;
  gpiod_chip* chip_ = nullptr;
  gpiod_line* led_ = nullptr;
  gpiod_line* trigger_ = nullptr;
  bool led_on_ = false;      ///< level last set (logical)
  bool trigger_on_ = false;
  core::ExposurePlan plan_{};
  EdgeSchedule schedule_{};
  std::int64_t spin_ns_ = 0;
  std::int64_t late_limit_ns_ = 0;
  std::int64_t trigger_pulse_ns_ = 0;
};

}  // namespace gvs::drivers
