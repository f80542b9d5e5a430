// See gvs/dsp/ground_plane.hpp for the maths.
#include "gvs/dsp/ground_plane.hpp"

#include <cmath>

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

core::RideHeight ground_from_points(const core::Vec3& p1, const core::Vec3& p2, const core::Vec3& p3,
                                    double mount_yaw_deg) {
  core::RideHeight ride;
  core::Vec3 n = core::cross(p2 - p1, p3 - p1);
  const double len = std::sqrt(core::dot(n, n));
  // Points in a line (or on top of each other): no plane.
  const double span = std::sqrt(core::dot(p2 - p1, p2 - p1) * core::dot(p3 - p1, p3 - p1));
  if (!(len > 1e-3 * span) || !(span > 0.0)) return ride;
  n = (1.0 / len) * n;
  if (n.z < 0.0) n = -1.0 * n;
  if (!(n.z > 0.1)) return ride;  // a "ground" steeper than 84 deg is not the ground
  ride.has_height = true;
  ride.height_mm = -core::dot(n, p1) / n.z;
  // Head axes -> vehicle axes: turned by the mount yaw about z.
  const double m = core::deg_to_rad(mount_yaw_deg);
  const double nx = std::cos(m) * n.x - std::sin(m) * n.y;
  const double ny = std::sin(m) * n.x + std::cos(m) * n.y;
  ride.has_tilt = true;
  ride.pitch_deg = core::rad_to_deg(-std::asin(nx));
  ride.roll_deg = core::rad_to_deg(std::atan2(ny, n.z));
  return ride;
}

void correct_velocity(const core::RideHeight& ride, double nominal_height_mm, double& vx_mps, double& vy_mps) {
  const double k = ride.height_mm / nominal_height_mm;
  if (!ride.has_tilt) {
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
