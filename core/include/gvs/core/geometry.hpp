// Angles and the mapping between image motion and vehicle velocity.
//
// Conventions (shared/spec/dataset-format.md, ISO 8855): vehicle x forward,
// y left; image rows grow towards the rear, columns towards the right, for a
// camera with mount_yaw_deg = 0. A ground point therefore moves in the image
// by d_row = +vx*dt/s, d_col = +vy*dt/s (s = metres per pixel): image motion
// *is* the vehicle velocity in camera axes, scaled by dt/s.
#pragma once

#include <cmath>
#include <numbers>

#include "gvs/core/frame.hpp"

namespace gvs::core {

constexpr double kPi = std::numbers::pi;

constexpr double deg_to_rad(double deg) { return deg * kPi / 180.0; }
constexpr double rad_to_deg(double rad) { return rad * 180.0 / kPi; }
constexpr double kmh_to_mps(double kmh) { return kmh / 3.6; }
constexpr double mps_to_kmh(double mps) { return mps * 3.6; }

/// Wraps an angle to (-180, 180] degrees.
inline double wrap_deg(double deg) {
  double w = std::fmod(deg, 360.0);
  if (w <= -180.0) w += 360.0;
  if (w > 180.0) w -= 360.0;
  return w;
}

/// Wraps an axis angle (a direction known up to its sign) to (-90, 90] degrees.
inline double wrap_axis_deg(double deg) {
  double w = std::fmod(deg, 180.0);
  if (w <= -90.0) w += 180.0;
  if (w > 90.0) w -= 180.0;
  return w;
}

/// Planar vector in vehicle axes (x forward, y left).
struct Vec2 {
  double x = 0.0;
  double y = 0.0;
};

/// Rotates a camera-axes vector into vehicle axes (camera yawed by
/// mount_yaw_deg, counter-clockwise seen from above).
inline Vec2 camera_to_vehicle(Vec2 v_cam, double mount_yaw_deg) {
  const double a = deg_to_rad(mount_yaw_deg);
  const double c = std::cos(a);
  const double s = std::sin(a);
  return {c * v_cam.x - s * v_cam.y, s * v_cam.x + c * v_cam.y};
}

/// Rotates a vehicle-axes vector into camera axes (inverse of camera_to_vehicle).
inline Vec2 vehicle_to_camera(Vec2 v_veh, double mount_yaw_deg) {
  return camera_to_vehicle(v_veh, -mount_yaw_deg);
}

/// Vehicle velocity (m/s) from a ground-texture displacement in the image of
/// (d_row_px, d_col_px) over dt_s seconds.
inline Vec2 image_shift_to_velocity(double d_row_px, double d_col_px, double dt_s,
                                    const CameraGeometry& cam) {
  const double m_per_px = cam.mm_per_px / 1000.0;
  const Vec2 v_cam{d_row_px * m_per_px / dt_s, d_col_px * m_per_px / dt_s};
  return camera_to_vehicle(v_cam, cam.mount_yaw_deg);
}

/// Image displacement (rows, cols) in pixels of the ground texture for a
/// vehicle velocity over dt_s seconds (inverse of image_shift_to_velocity).
inline Vec2 velocity_to_image_shift(Vec2 v_veh_mps, double dt_s, const CameraGeometry& cam) {
  const double m_per_px = cam.mm_per_px / 1000.0;
  const Vec2 v_cam = vehicle_to_camera(v_veh_mps, cam.mount_yaw_deg);
  return {v_cam.x * dt_s / m_per_px, v_cam.y * dt_s / m_per_px};
}

/// v / |v|, or (1, 0) for the zero vector.
inline Vec2 unit_vector(Vec2 v) {
  const double n = std::hypot(v.x, v.y);
  return n > 0.0 ? Vec2{v.x / n, v.y / n} : Vec2{1.0, 0.0};
}

/// Direction of travel, atan2(vy, vx) in degrees, (-180, 180].
inline double direction_deg(Vec2 v) { return wrap_deg(rad_to_deg(std::atan2(v.y, v.x))); }

/// The body's attitude R = Ry(pitch) Rx(roll) (ISO 8855 z-y-x: pitch + nose
/// down, roll + right side down): its bottom row (where the body's z axis
/// points) and the 2x2 map A = r_zz R_xy - r_xz,yz r_zx,zy that takes a level
/// ground displacement to the tilted camera's, up to the perspective
/// divisor. The simulator's projection (drivers/src/sim/camera_view.hpp) and
/// the laser dots' velocity correction (dsp/src/lasers/ground_plane.cpp)
/// share it.
struct TiltMap {
  double rzx, rzy, rzz;
  double axx, axy, ayx, ayy;
};

inline TiltMap tilt_map(double pitch_rad, double roll_rad) {
  const double ct = std::cos(pitch_rad), st = std::sin(pitch_rad), cf = std::cos(roll_rad), sf = std::sin(roll_rad);
  const double rxx = ct, rxy = st * sf, rxz = st * cf;
  const double ryx = 0.0, ryy = cf, ryz = -sf;
  const double rzx = -st, rzy = ct * sf, rzz = ct * cf;
  return {rzx,
          rzy,
          rzz,
          rzz * rxx - rxz * rzx,
          rzz * rxy - rxz * rzy,
          rzz * ryx - ryz * rzx,
          rzz * ryy - ryz * rzy};
}

}  // namespace gvs::core
