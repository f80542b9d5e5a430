// The laser dots of the sensor head: where each beam starts and where it
// points (docs/hardware.md, "Laser dots"). Shared by the simulator, which
// renders the dots, the finder in gvs::dsp, which triangulates them, and the
// dataset's camera.json (key "lasers"), which records them.
//
// Head axes: the camera's own axes, origin at the optical centre, x towards
// the top of the image (the vehicle's forward for mount_yaw_deg = 0), y
// towards the image's left, z up along the optical axis (the camera looks
// along -z). Pixel (r, c) looks along (a, b, -1) with
//   a = -(r - rc) / f,  b = -(c - cc) / f,  f = H0 / s0 px
// (s0 = mm_per_px at the nominal height H0; rc, cc the image centre).
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>

#include "gvs/core/frame.hpp"
#include "gvs/core/geometry.hpp"

namespace gvs::core {

struct Vec3 {
  double x = 0.0;
  double y = 0.0;
  double z = 0.0;
};

inline Vec3 operator+(Vec3 a, Vec3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
inline Vec3 operator-(Vec3 a, Vec3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
inline Vec3 operator*(double k, Vec3 a) { return {k * a.x, k * a.y, k * a.z}; }
inline double dot(Vec3 a, Vec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
inline Vec3 cross(Vec3 a, Vec3 b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }

/// One laser: a thin beam from its exit window, in head axes.
struct LaserBeam {
  double x_mm = 0.0;  ///< exit point, head axes, mm from the optical centre
  double y_mm = 0.0;
  double z_mm = 0.0;  ///< negative: below the optical centre (the head's window)
  double azimuth_deg = 0.0;  ///< direction of the beam's horizontal part, CCW from head x
  double tilt_deg = 45.0;    ///< angle from straight down (head -z)

  [[nodiscard]] Vec3 origin_mm() const { return {x_mm, y_mm, z_mm}; }
  /// Unit vector along the beam.
  [[nodiscard]] Vec3 direction() const {
    const double t = deg_to_rad(tilt_deg);
    const double a = deg_to_rad(azimuth_deg);
    return {std::sin(t) * std::cos(a), std::sin(t) * std::sin(a), -std::cos(t)};
  }
};

/// The head's lasers (none: count = 0) and what the finder needs to know
/// about their spots.
struct LaserGeometry {
  static constexpr std::size_t kMaxBeams = 4;
  std::size_t count = 0;
  std::array<LaserBeam, kMaxBeams> beams{};
  /// Spot on the ground, Gaussian sigma across the beam (1/e^2 radius / 2), mm.
  double spot_sigma_mm = 0.1;
  /// Heights the finder searches, mm (the dot's track in the image is
  /// clipped to the frame as well).
  double min_height_mm = 45.0;
  double max_height_mm = 80.0;

  [[nodiscard]] bool enabled() const { return count > 0; }
};

/// Pixel (row, col) of a point in head axes (z < 0), pinhole of focal
/// length f = H0 / s0 px about the image centre.
inline void head_to_pixel(const CameraGeometry& cam, double nominal_height_mm, Vec3 p, double& row, double& col) {
  const double f = nominal_height_mm / cam.mm_per_px;
  const double rc = 0.5 * (cam.height_px - 1);
  const double cc = 0.5 * (cam.width_px - 1);
  row = rc - f * p.x / -p.z;
  col = cc - f * p.y / -p.z;
}

/// Line of sight of pixel (row, col) in head axes: (a, b, -1).
inline Vec3 pixel_ray(const CameraGeometry& cam, double nominal_height_mm, double row, double col) {
  const double f = nominal_height_mm / cam.mm_per_px;
  const double rc = 0.5 * (cam.height_px - 1);
  const double cc = 0.5 * (cam.width_px - 1);
  return {-(row - rc) / f, -(col - cc) / f, -1.0};
}

/// The design's dots for a camera at its nominal height (docs/hardware.md,
/// "Laser dots"): beams at 45 deg from exits 20 mm below the optical centre,
/// landing on a level ground at the nominal height at (0.73 X, 0.12 Y),
/// (-0.73 X, -0.12 Y), (0, -0.78 Y) and (0, 0.78 Y) (X, Y: half the field of
/// view along head x and y; 14, 3 / -14, -3 / 0, -20 / 0, 20 mm for
/// 512 x 384 px at 0.1 mm/px), the first two moving along y with the height,
/// the others along x, so that no two tracks cross between 45 and 80 mm
/// (they pass 16 px apart at the closest). Three fix the plane; the fourth
/// checks it (a bright grain taken for a dot does not fit) and stands in
/// for one that is not found. `beams` = 3 leaves the fourth out.
inline LaserGeometry design_laser_geometry(const CameraGeometry& cam, double nominal_height_mm, std::size_t beams = 4) {
  const double half_x = 0.5 * cam.height_px * cam.mm_per_px;
  const double half_y = 0.5 * cam.width_px * cam.mm_per_px;
  constexpr double kExitZ = -20.0;
  constexpr double kTilt = 45.0;
  LaserGeometry g;
  g.count = std::clamp<std::size_t>(beams, 1, LaserGeometry::kMaxBeams);
  struct Landing {
    double x, y, azimuth_deg;
  };
  const std::array<Landing, LaserGeometry::kMaxBeams> land = {
      Landing{0.73 * half_x, 0.12 * half_y, -90.0}, Landing{-0.73 * half_x, -0.12 * half_y, 90.0},
      Landing{0.0, -0.78 * half_y, 180.0}, Landing{0.0, 0.78 * half_y, 0.0}};
  const double run = (nominal_height_mm + kExitZ) * std::tan(deg_to_rad(kTilt));  // horizontal travel to the ground
  for (std::size_t k = 0; k < g.count; ++k) {
    const double az = deg_to_rad(land[k].azimuth_deg);
    LaserBeam& b = g.beams[k];
    b.x_mm = std::round(100.0 * (land[k].x - run * std::cos(az))) / 100.0;  // as drawn: 0.01 mm
    b.y_mm = std::round(100.0 * (land[k].y - run * std::sin(az))) / 100.0;
    b.z_mm = kExitZ;
    b.azimuth_deg = land[k].azimuth_deg;
    b.tilt_deg = kTilt;
  }
  return g;
}

}  // namespace gvs::core
