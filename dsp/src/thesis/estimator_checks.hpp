// What every thesis estimator checks of a frame and how it fills an estimate
// (shared by estimators.cpp and orb_estimators.cpp).
#pragma once

#include <cmath>
#include <optional>

#include "gvs/dsp/estimator.hpp"
#include "gvs/dsp/vocabulary.hpp"

namespace gvs::dsp::thesis {

/// Why this frame cannot be measured, or nothing.
inline std::optional<Method> frame_problem(const FrameView& f, const CameraGeometry& cam) {
  if (f.gray.empty()) return Method::empty_frame;
  if (f.gray.type() != CV_8UC1) return Method::bad_format;
  if (f.gray.cols != cam.width_px || f.gray.rows != cam.height_px) return Method::wrong_size;
  return std::nullopt;
}

inline void set_velocity(VelocityEstimate& e, Vec2 v) {
  e.vx_mps = v.x;
  e.vy_mps = v.y;
  e.speed_mps = std::hypot(v.x, v.y);
  e.has_speed = true;
  e.has_direction = e.speed_mps >= VelocityEstimate::kStandstillMps;
  e.direction_deg = e.has_direction ? direction_deg(v) : 0.0;
}

}  // namespace gvs::dsp::thesis
