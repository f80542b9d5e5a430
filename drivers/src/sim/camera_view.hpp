// Where each pixel's line of sight meets the ground: a pinhole camera whose
// optical axis is the vehicle's -z axis, at a height above the ground that
// moves with the body, tilted by the body's pitch and roll
// (docs/simulator.md, "Body motion").
//
// Pixel (r, c) looks along d = (a', b', -1) in vehicle axes, where (a', b')
// is the mount-yaw rotation of the normalised image coordinates
//   a = -(r - rc) s0 / H0,  b = -(c - cc) s0 / H0
// (s0 = mm_per_px at the nominal height H0: f = H0 / s0 px). The body's
// attitude R = Ry(pitch) Rx(roll) (ISO 8855, z-y-x) turns d into level
// axes; the optical centre is at R (0, 0, H) from the point where the
// vehicle's z axis meets the ground (H = height along that axis, the truth's
// height_mm), and the ray meets the ground at that point plus
//   G = H [A (a', b')] / w,  w = R_zz - R_zx a' - R_zy b',
//   A = [[R_zz R_xx - R_xz R_zx, R_zz R_xy - R_xz R_zy],
//        [R_zz R_yx - R_yz R_zx, R_zz R_yy - R_yz R_zy]]
// (solve for the ray parameter where the height is zero). Level: A = I, w = 1,
// G = (H / H0) s0 (-(r - rc), -(c - cc)) rotated by the mount yaw: the
// orthographic view scaled by H / H0. Tilted: a homography, whose scale
// varies across the frame. The image centre always sees the pose's point,
// so the scenario's velocity is that of the ground under the image centre.
#pragma once

#include <cmath>
#include <numbers>

#include "gvs/core/geometry.hpp"
#include "gvs/drivers/sim/scenario.hpp"

namespace gvs::drivers::sim {

struct CameraFrame {
  double s_mm;  ///< mm per px at the nominal height
  double rc;    ///< image centre row
  double cc;    ///< image centre column
  double mount_rad;
  int width;
  int height;
  double height_mm;  ///< nominal height H0 (where s_mm holds)
};

/// Pixel -> world ground point (mm) at one instant: x = X(r, c) / W(r, c),
/// y = Y(r, c) / W(r, c), with X, Y, W affine in (r, c). Level body: W = 1.
struct ViewMap {
  double x00, xr, xc;
  double y00, yr, yc;
  double w00, wr, wc;
  bool projective;  ///< tilted (W varies); false: affine, W = 1

  void world(double r, double c, double& x, double& y) const {
    const double w = w00 + r * wr + c * wc;
    x = (x00 + r * xr + c * xc) / w;
    y = (y00 + r * yr + c * yc) / w;
  }
};

[[nodiscard]] inline bool is_level(const BodyPose& b) { return b.pitch_deg == 0.0 && b.roll_deg == 0.0; }

/// Scale of the level view against the nominal one, H / H0. Exactly 1 at the
/// nominal height, so the frames of a run without body motion are the same
/// bit for bit as before body motion existed.
[[nodiscard]] inline double level_scale(const CameraFrame& cam, const BodyPose& b) {
  return (cam.height_mm + b.heave_mm) / cam.height_mm;
}

/// The view of a tilted (or level) body at pose p as a ViewMap.
[[nodiscard]] inline ViewMap view_map(const CameraFrame& cam, const Pose& p, const BodyPose& b) {
  constexpr double kDeg = std::numbers::pi / 180.0;
  const double th = b.pitch_deg * kDeg;
  const double ph = b.roll_deg * kDeg;
  // R = Ry(pitch) Rx(roll) and the tilted ground's map (core::tilt_map).
  const core::TiltMap t = core::tilt_map(th, ph);
  const double rzx = t.rzx, rzy = t.rzy, rzz = t.rzz;
  const double axx = t.axx, axy = t.axy, ayx = t.ayx, ayy = t.ayy;
  // (a', b') = k M (r - rc, c - cc), k = s0 / H0, M = Rz(mount) (-I).
  const double k = cam.s_mm / cam.height_mm;
  const double cm = std::cos(cam.mount_rad), sm = std::sin(cam.mount_rad);
  // a' = ar r + ac c + a0, b' = br r + bc c + b0.
  const double ar = -k * cm, ac = k * sm, br = -k * sm, bc = -k * cm;
  const double a0 = -(ar * cam.rc + ac * cam.cc), b0 = -(br * cam.rc + bc * cam.cc);
  const double hh = cam.height_mm + b.heave_mm;
  // G (times w) and w, affine in (r, c).
  const double gx0 = hh * (axx * a0 + axy * b0), gxr = hh * (axx * ar + axy * br), gxc = hh * (axx * ac + axy * bc);
  const double gy0 = hh * (ayx * a0 + ayy * b0), gyr = hh * (ayx * ar + ayy * br), gyc = hh * (ayx * ac + ayy * bc);
  const double w0 = rzz - rzx * a0 - rzy * b0, wr = -rzx * ar - rzy * br, wc = -rzx * ac - rzy * bc;
  // World: p + Rz(yaw) G, i.e. (p w + Rz(yaw) G w) / w.
  const double cy = std::cos(p.yaw_rad), sy = std::sin(p.yaw_rad);
  const double px = p.x_m * 1000.0, py = p.y_m * 1000.0;
  ViewMap m{};
  m.x00 = px * w0 + cy * gx0 - sy * gy0;
  m.xr = px * wr + cy * gxr - sy * gyr;
  m.xc = px * wc + cy * gxc - sy * gyc;
  m.y00 = py * w0 + sy * gx0 + cy * gy0;
  m.yr = py * wr + sy * gxr + cy * gyr;
  m.yc = py * wc + sy * gxc + cy * gyc;
  m.w00 = w0;
  m.wr = wr;
  m.wc = wc;
  m.projective = !is_level(b);
  return m;
}

/// World point (mm) seen by pixel (r, c) at pose p with body pose b. A level
/// body takes the orthographic formula scaled by H / H0 (the frames of runs
/// without body motion stay what they were); a tilted one the homography.
inline void pixel_world(const CameraFrame& cam, const Pose& p, const BodyPose& b, double r, double c, double& x,
                        double& y) {
  if (!is_level(b)) {
    view_map(cam, p, b).world(r, c, x, y);
    return;
  }
  const double s = cam.s_mm * level_scale(cam, b);
  const double xc = -(r - cam.rc) * s;
  const double yc = -(c - cam.cc) * s;
  const double phi = p.yaw_rad + cam.mount_rad;
  const double cp = std::cos(phi);
  const double sp = std::sin(phi);
  x = p.x_m * 1000.0 + cp * xc - sp * yc;
  y = p.y_m * 1000.0 + sp * xc + cp * yc;
}

}  // namespace gvs::drivers::sim
