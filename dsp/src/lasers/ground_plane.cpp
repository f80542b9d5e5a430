// See gvs/dsp/ground_plane.hpp for the maths.
#include "gvs/dsp/ground_plane.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace gvs::dsp {

bool triangulate(const core::LaserBeam& beam, core::Vec3 sight, core::Vec3& point_mm) {
  const core::Vec3 o = beam.origin_mm();
  const core::Vec3 u = beam.direction();
  const double uu = core::dot(u, u), ud = core::dot(u, sight), dd = core::dot(sight, sight);
  const double ou = core::dot(o, u), od = core::dot(o, sight);
  // [uu -ud; ud -dd] [t; s] = [-ou; -od]  (Cramer's rule)
  const double det = -uu * dd + ud * ud;
  if (std::abs(det) < 1e-9 * uu * dd) return false;
  const double t = (-ou * -dd - -ud * -od) / det;
  point_mm = o + t * u;
  return t > 0.0;
}

bool beam_on_plane(const core::LaserBeam& beam, const core::Vec3& p1, const core::Vec3& p2, const core::Vec3& p3,
                   core::Vec3& point_mm) {
  const core::Vec3 n = core::cross(p2 - p1, p3 - p1);
  const core::Vec3 o = beam.origin_mm();
  const core::Vec3 u = beam.direction();
  const double nu = core::dot(n, u);
  if (!(std::abs(nu) > 1e-9 * std::sqrt(core::dot(n, n)))) return false;
  const double t = core::dot(n, p1 - o) / nu;
  point_mm = o + t * u;
  return t > 0.0;
}

namespace {

/// The points' mean, and their scatter about it: S = [Sxx Sxy; Sxy Syy]
/// and the products with z the plane fit needs.
struct PointScatter {
  core::Vec3 mean;
  double sxx = 0.0, sxy = 0.0, syy = 0.0, sxz = 0.0, syz = 0.0;
};

PointScatter scatter_about_mean(const core::Vec3* points, std::size_t count) {
  PointScatter s;
  for (std::size_t k = 0; k < count; ++k) s.mean = s.mean + points[k];
  s.mean = (1.0 / static_cast<double>(count)) * s.mean;
  for (std::size_t k = 0; k < count; ++k) {
    const core::Vec3 d = points[k] - s.mean;
    s.sxx += d.x * d.x;
    s.sxy += d.x * d.y;
    s.syy += d.y * d.y;
    s.sxz += d.x * d.z;
    s.syz += d.y * d.z;
  }
  return s;
}

/// Height where the optical axis meets the plane through `p` with unit
/// normal `n` (n.z > 0), and its pitch and roll in vehicle axes.
core::RideHeight ground_from_normal(core::Vec3 n, const core::Vec3& p, double mount_yaw_deg) {
  core::RideHeight ride;
  if (!(n.z > 0.1)) return ride;  // a "ground" steeper than 84 deg is not the ground
  ride.has_height = true;
  ride.height_mm = -core::dot(n, p) / n.z;
  // Head axes -> vehicle axes: turned by the mount yaw about z.
  const double m = core::deg_to_rad(mount_yaw_deg);
  const double nx = std::cos(m) * n.x - std::sin(m) * n.y;
  const double ny = std::sin(m) * n.x + std::cos(m) * n.y;
  ride.has_pitch = ride.has_roll = true;
  ride.pitch_deg = core::rad_to_deg(-std::asin(nx));
  ride.roll_deg = core::rad_to_deg(std::atan2(ny, n.z));
  return ride;
}

}  // namespace

core::RideHeight ground_from_points(const core::Vec3& p1, const core::Vec3& p2, const core::Vec3& p3,
                                    double mount_yaw_deg) {
  core::Vec3 n = core::cross(p2 - p1, p3 - p1);
  const double len = std::sqrt(core::dot(n, n));
  // Points in a line (or on top of each other): no plane.
  const double span = std::sqrt(core::dot(p2 - p1, p2 - p1) * core::dot(p3 - p1, p3 - p1));
  if (!(len > 1e-3 * span) || !(span > 0.0)) return {};
  n = (1.0 / len) * n;
  if (n.z < 0.0) n = -1.0 * n;
  return ground_from_normal(n, p1, mount_yaw_deg);
}

core::RideHeight ground_from_fit(const core::Vec3* points, std::size_t count, double mount_yaw_deg,
                                 double& max_residual_mm) {
  max_residual_mm = 0.0;
  if (count < 3) return {};
  // Normal equations of z = c + a x + b y about the points' mean (better
  // conditioned): [Sxx Sxy; Sxy Syy] [a; b] = [Sxz; Syz], c = mz - a mx - b my.
  const auto [mean, sxx, sxy, syy, sxz, syz] = scatter_about_mean(points, count);
  const double det = sxx * syy - sxy * sxy;
  if (!(det > 1e-6 * (sxx + syy) * (sxx + syy))) return {};  // points in a line: no plane
  const double a = (sxz * syy - syz * sxy) / det;
  const double b = (syz * sxx - sxz * sxy) / det;
  const double norm = std::sqrt(a * a + b * b + 1.0);
  for (std::size_t k = 0; k < count; ++k) {
    const core::Vec3 d = points[k] - mean;
    max_residual_mm = std::max(max_residual_mm, std::abs(d.z - a * d.x - b * d.y) / norm);
  }
  return ground_from_normal({-a / norm, -b / norm, 1.0 / norm}, mean, mount_yaw_deg);
}

double tilt_doubt_deg(const core::Vec3* points, std::size_t count, double max_residual_mm) {
  if (count < 4) return std::numeric_limits<double>::infinity();
  const PointScatter s = scatter_about_mean(points, count);
  const core::Vec3& mean = s.mean;
  const double sxx = s.sxx, sxy = s.sxy, syy = s.syy;
  const double det = sxx * syy - sxy * sxy;
  if (!(det > 1e-6 * (sxx + syy) * (sxx + syy))) return std::numeric_limits<double>::infinity();
  double worst_rad_per_mm = 0.0;
  for (std::size_t k = 0; k < count; ++k) {
    const core::Vec3 dk = points[k] - mean;
    // S^-1 d_k: the slopes a unit error of point k gives.
    const double ga = (syy * dk.x - sxy * dk.y) / det;
    const double gb = (sxx * dk.y - sxy * dk.x) / det;
    double largest_residual = 0.0;
    for (std::size_t i = 0; i < count; ++i) {
      const core::Vec3 di = points[i] - mean;
      const double r = (i == k ? 1.0 : 0.0) - 1.0 / static_cast<double>(count) - (di.x * ga + di.y * gb);
      largest_residual = std::max(largest_residual, std::abs(r));
    }
    if (!(largest_residual > 1e-9)) return std::numeric_limits<double>::infinity();  // point k's error unseen
    worst_rad_per_mm = std::max(worst_rad_per_mm, std::hypot(ga, gb) / largest_residual);
  }
  return core::rad_to_deg(std::atan(worst_rad_per_mm * max_residual_mm));
}

TiltSigma tilt_sigma_deg(const core::Vec3* points, std::size_t count, double point_scatter_mm,
                         double mount_yaw_deg) {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  if (count < 3) return {kInf, kInf};
  const PointScatter s = scatter_about_mean(points, count);
  const double det = s.sxx * s.syy - s.sxy * s.sxy;
  if (!(det > 1e-6 * (s.sxx + s.syy) * (s.sxx + s.syy))) return {kInf, kInf};  // points in a line
  // C = S^-1 = [Syy -Sxy; -Sxy Sxx] / det, turned by the mount yaw m as the
  // normal is in ground_from_normal: (R C R^T)_xx and _yy, R = [c -s; s c].
  const double cxx = s.syy / det, cyy = s.sxx / det, cxy = -s.sxy / det;
  const double m = core::deg_to_rad(mount_yaw_deg);
  const double c = std::cos(m), sn = std::sin(m);
  const double var_pitch = c * c * cxx - 2.0 * c * sn * cxy + sn * sn * cyy;
  const double var_roll = sn * sn * cxx + 2.0 * c * sn * cxy + c * c * cyy;
  return {core::rad_to_deg(std::atan(point_scatter_mm * std::sqrt(var_pitch))),
          core::rad_to_deg(std::atan(point_scatter_mm * std::sqrt(var_roll)))};
}

void correct_velocity(const core::RideHeight& ride, double nominal_height_mm, double& vx_mps, double& vy_mps) {
  const double k = ride.height_mm / nominal_height_mm;
  if (!ride.has_tilt()) {
    vx_mps *= k;
    vy_mps *= k;
    return;
  }
  // The simulator's projection at the optical axis (core::tilt_map).
  const core::TiltMap t = core::tilt_map(core::deg_to_rad(ride.pitch_deg), core::deg_to_rad(ride.roll_deg));
  const double vx = vx_mps, vy = vy_mps;
  vx_mps = k * (t.axx * vx + t.axy * vy) / t.rzz;
  vy_mps = k * (t.ayx * vx + t.ayy * vy) / t.rzz;
}

}  // namespace gvs::dsp
