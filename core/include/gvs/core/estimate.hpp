// The estimator's output for one frame, in ISO 8855 vehicle axes.
#pragma once

#include <cstdint>

#include "gvs/core/method.hpp"
#include "gvs/core/ride_height.hpp"

namespace gvs::core {

/// Velocity of the sensor over the ground, as estimated from one frame (and,
/// for pair methods, the one before it). Fields without their `has_` flag are
/// meaningless and must not be used.
struct VelocityEstimate {
  std::int64_t index = 0;
  std::int64_t t_ns = 0;  ///< time the estimate refers to: the frame's mid-exposure

  bool has_speed = false;
  bool has_direction = false;
  bool has_yaw_rate = false;

  double vx_mps = 0.0;  ///< forward
  double vy_mps = 0.0;  ///< left
  double speed_mps = 0.0;
  double direction_deg = 0.0;  ///< atan2(vy, vx), (-180, 180]
  double yaw_rate_dps = 0.0;   ///< CCW from above

  double quality = 0.0;  ///< [0, 1]; 0 = nothing measured
  /// Texture power over the sensor's noise in this frame (single-frame and
  /// double-pulse analyses; 0 = not measured). When it is low the exposure
  /// controller lengthens the double-pulse pulses, or in adaptive mode
  /// takes the longest exposure (more light).
  double texture_snr = 0.0;
  /// How well lit the frame is, whatever its texture: mean grey over the RMS
  /// of its white noise (shot, read, fixed pattern) per pixel (single-frame
  /// analysis; 0 = not measured). A long streak also leaves a low
  /// texture_snr (the blur removes the texture's power), but only a frame
  /// that is not well_lit() is short of light.
  double pixel_snr = 0.0;
  /// The estimator had measured a speed shortly before this frame (and looked
  /// for this frame's speed near it). Without it, a missing speed is a
  /// start-up miss: the exposure controller then searches the exposures.
  bool tracking = false;
  /// The measurement that produced the estimate, or why there is none
  /// (Method::dark, Method::no_texture, ...); its word is the estimates CSV's
  /// `method` column and its code the CAN signal GVS_Method.
  Method method = Method::none;
  /// The height and tilt measured in this frame (laser dots), if any.
  RideHeight ride;
  /// The height vx, vy and speed_mps are scaled with.
  ScaleSource scale_source = ScaleSource::nominal;

  /// vx, vy are known when speed and direction are, or when the car stands.
  [[nodiscard]] bool has_velocity_xy() const {
    return has_speed && (has_direction || speed_mps < kStandstillMps);
  }

  /// Enough light that a faint texture means blur, not darkness: the
  /// simulator's normal light at 3 ms gives a pixel SNR of 38-56 (procedural
  /// and photographed ground), its under-exposed frames 18 (docs/estimator.md,
  /// "Dark or blurred").
  [[nodiscard]] bool well_lit() const { return pixel_snr >= kWellLitPixelSnr; }

  static constexpr double kStandstillMps = 0.01;
  static constexpr double kWellLitPixelSnr = 25.0;
};

/// An estimate that says "nothing measured, because `reason`".
inline VelocityEstimate no_estimate(std::int64_t index, std::int64_t t_ns, Method reason) {
  VelocityEstimate e;
  e.index = index;
  e.t_ns = t_ns;
  e.quality = 0.0;
  e.method = reason;
  return e;
}

}  // namespace gvs::core
