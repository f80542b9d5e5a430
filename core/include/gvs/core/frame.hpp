// What the estimators see of one camera frame, and how it was exposed.
#pragma once

#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>

#include <opencv2/core/mat.hpp>

namespace gvs::core {

/// One light pulse inside an exposure, relative to the exposure start.
struct LightPulse {
  double start_us = 0.0;
  double duration_us = 0.0;
};

/// How a frame was exposed. With no pulses the sensor integrated light
/// continuously for `exposure_us`; with pulses, only while each pulse was on
/// (the LED strobe is the only light under the car floor).
struct ExposurePlan {
  static constexpr std::size_t kMaxPulses = 8;

  double exposure_us = 3000.0;
  std::array<LightPulse, kMaxPulses> pulses{};
  std::size_t pulse_count = 0;

  /// Total time light reached the sensor, in microseconds.
  [[nodiscard]] double lit_time_us() const {
    if (pulse_count == 0) return exposure_us;
    double sum = 0.0;
    for (std::size_t i = 0; i < pulse_count; ++i) sum += pulses[i].duration_us;
    return sum;
  }
  /// Mid-point of the light (energy-weighted centre), microseconds after the exposure start.
  [[nodiscard]] double light_centre_us() const {
    if (pulse_count == 0) return exposure_us / 2.0;
    double weighted = 0.0;
    double total = 0.0;
    for (std::size_t i = 0; i < pulse_count; ++i) {
      weighted += (pulses[i].start_us + pulses[i].duration_us / 2.0) * pulses[i].duration_us;
      total += pulses[i].duration_us;
    }
    return total > 0.0 ? weighted / total : exposure_us / 2.0;
  }
};

/// The time a frame describes: its exposure start plus the light's centre
/// (light_centre_us(), mid-exposure for a continuous exposure), rounded to
/// the nearest nanosecond. Estimates, truth rows and the CAN age all use
/// this one instant, so they agree to the nanosecond.
[[nodiscard]] inline std::int64_t mid_exposure_ns(std::int64_t exposure_start_ns, const ExposurePlan& exposure) {
  return exposure_start_ns + static_cast<std::int64_t>(std::llround(exposure.light_centre_us() * 1000.0));
}

/// One frame as the estimators take it. `gray` is CV_8UC1; the view does not
/// own the pixels (the daemon's ring or the replay reader does).
struct FrameView {
  cv::Mat gray;
  std::int64_t index = 0;
  std::int64_t t_ns = 0;  ///< start of the exposure, monotonic clock
  ExposurePlan exposure;
};

/// Camera geometry on the car (dataset camera.json / daemon config).
struct CameraGeometry {
  int width_px = 512;
  int height_px = 384;
  double mm_per_px = 0.1;
  double mount_yaw_deg = 0.0;  ///< camera rotation about z vs. nominal, CCW from above
};

}  // namespace gvs::core
