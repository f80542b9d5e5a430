// The bridge between the estimator's output and the CAN library, which does
// not know the estimate type: the estimate as the bus sees it, and GVS_Method's
// words for `gvs monitor`.
#pragma once

#include <cstdint>
#include <optional>

#include "gvs/can/codec.hpp"
#include "gvs/core/estimate.hpp"
#include "gvs/core/method.hpp"

namespace gvs::daemon {

// core::ScaleSource and GVS_ScaleSource share their codes.
static_assert(static_cast<int>(can::ScaleSourceCode::Nominal) == static_cast<int>(core::ScaleSource::nominal));
static_assert(static_cast<int>(can::ScaleSourceCode::LaserDots) == static_cast<int>(core::ScaleSource::laser_dots));
static_assert(static_cast<int>(can::ScaleSourceCode::External) == static_cast<int>(core::ScaleSource::external));

inline can::BusEstimate bus_estimate(const core::VelocityEstimate& e) noexcept {
  can::BusEstimate b;
  b.t_ns = e.t_ns;
  b.has_speed = e.has_speed;
  b.has_direction = e.has_direction;
  b.has_yaw_rate = e.has_yaw_rate;
  b.has_velocity_xy = e.has_velocity_xy();
  b.speed_mps = e.speed_mps;
  b.direction_deg = e.direction_deg;
  b.yaw_rate_dps = e.yaw_rate_dps;
  b.vx_mps = e.vx_mps;
  b.vy_mps = e.vy_mps;
  b.quality = e.quality;
  b.method_code = core::method_can_code(e.method);
  b.scale_source = static_cast<can::ScaleSourceCode>(e.scale_source);
  b.has_height = e.ride.has_height;
  b.height_mm = e.ride.height_mm;
  b.has_pitch = e.ride.has_pitch;
  b.pitch_deg = e.ride.pitch_deg;
  b.has_roll = e.ride.has_roll;
  b.roll_deg = e.ride.roll_deg;
  return b;
}

/// The estimates CSV word of a GVS_Method code; nullptr for a code not in core::kMethods.
inline const char* method_word_of_code(std::uint8_t code) noexcept {
  const std::optional<core::Method> m = core::method_from_can_code(code);
  return m ? core::method_word(*m) : nullptr;
}

}  // namespace gvs::daemon
