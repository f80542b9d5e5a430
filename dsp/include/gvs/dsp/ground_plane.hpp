// The ground under the sensor from the laser dots, and the speed's scale
// from the ground (docs/estimator.md, "Height from the laser dots").
//
// 1. Triangulation. A dot seen at pixel (r, c) lies on the camera's line of
//    sight s d, d = (a, b, -1) (core/laser_geometry.hpp), and on its laser
//    beam O + t u. Both are known lines; the dot is where they meet. With
//    noise they miss each other slightly, so take the t that brings them
//    closest (least squares, two equations in t and s):
//        t (u.u) - s (u.d) = -O.u
//        t (u.d) - s (d.d) = -O.d
//    and the point P = O + t u on the beam.
// 2. Plane. Three points P1, P2, P3 fix the ground plane: its normal
//    n = (P2 - P1) x (P3 - P1) (made unit, pointing up); the camera's height
//    H along its own z axis is where that axis (0, 0, -H) meets the plane:
//        H = -(n . P1) / n_z.
//    In vehicle axes (the head turned by the mount yaw) the ground's normal
//    is the third row of the body's attitude R = Ry(pitch) Rx(roll) (ISO
//    8855): n = (-sin pitch, cos pitch sin roll, cos pitch cos roll), so
//        pitch = -asin(n_x),  roll = atan2(n_y, n_z).
//    Four points over-determine it: fit z = c + a x + b y by least squares
//    (normal equations; the ground is within a few degrees of level, so z
//    is a function of x and y), n = (-a, -b, 1) / |(-a, -b, 1)|, H = -c;
//    each point's distance from the fitted plane,
//        |z_k - c - a x_k - b y_k| / |(-a, -b, 1)|,
//    tells whether the four agree (a bright grain taken for a dot does not).
// 3. Scale. The estimators turn image motion into velocity with the
//    nominal scale s0 (mm per px at the nominal height H0). A ground point
//    under the image centre moves in the image by d(a', b') (normalised
//    vehicle-axes image coordinates); on the ground that is
//        dG = H (A / R_zz) d(a', b'),  A = [[Rzz Rxx - Rxz Rzx, Rzz Rxy - Rxz Rzy],
//                                        [Rzz Ryx - Ryz Rzx, Rzz Ryy - Ryz Rzy]]
//    (solve the line of sight for the ground, docs/simulator.md,
//    "Projection"), while the estimators assumed dG = H0 d(a', b'). So
//        v = (H / H0) (A / R_zz) v_nominal.
//    Level: v = (H / H0) v_nominal, the whole of the first-order effect
//    (5 mm in 60 mm: 8 %). The tilt's part is second order at the centre
//    (1 / cos 1.5 deg - 1 = 0.03 %).
#pragma once

#include <cstddef>

#include "gvs/core/laser_geometry.hpp"
#include "gvs/core/ride_height.hpp"

namespace gvs::dsp {

/// The point of beam `beam` seen along the line of sight `sight` (head
/// axes). False when the two lines are (nearly) parallel.
bool triangulate(const core::LaserBeam& beam, core::Vec3 sight, core::Vec3& point_mm);

/// Where beam `beam` meets the plane through p1, p2, p3 (head axes): the
/// point O + t u with n.(O + t u - p1) = 0, n = (p2 - p1) x (p3 - p1).
/// False when the beam runs along the plane or meets it behind its origin.
bool beam_on_plane(const core::LaserBeam& beam, const core::Vec3& p1, const core::Vec3& p2, const core::Vec3& p3,
                   core::Vec3& point_mm);

/// Height at the optical axis and the ground's pitch and roll (vehicle
/// axes, ISO 8855) from three ground points in head axes. has_height,
/// has_pitch and has_roll stay false when the points are (nearly) in a line.
core::RideHeight ground_from_points(const core::Vec3& p1, const core::Vec3& p2, const core::Vec3& p3,
                                    double mount_yaw_deg);

/// Height, pitch and roll from the least-squares plane through `count` (3 or
/// more) ground points in head axes, and the largest point's distance from
/// it (`max_residual_mm`). has_height, has_pitch and has_roll stay false
/// when the points do not fix a plane.
core::RideHeight ground_from_fit(const core::Vec3* points, std::size_t count, double mount_yaw_deg,
                                 double& max_residual_mm);

/// How far one wrong point could have tilted the least-squares plane of
/// `count` (4 or more) points (head axes) and still leave the largest
/// residual `max_residual_mm` the fit shows, deg. A point k that is e mm
/// off the ground moves the plane's slopes (a, b) by e S^-1 d_k (d_k the
/// point about the mean, S the points' scatter matrix [Sxx Sxy; Sxy Syy])
/// and leaves residuals e (delta_ik - 1/n - d_i^T S^-1 d_k); the largest of
/// them is at most the residual seen, so e is at most that over it. The
/// worst point gives the bound (the design's four dots: 8.2 deg per mm of
/// residual, dot 0 or 1 moving the pitch over their 28 mm). Infinite for
/// three points (nothing to see a wrong one by).
double tilt_doubt_deg(const core::Vec3* points, std::size_t count, double max_residual_mm);

/// The scatter of the least-squares plane's pitch and of its roll, deg
/// (vehicle axes), when each point's height scatters by `point_scatter_mm`
/// on its own: least squares gives the slopes' covariance s^2 S^-1 (S the
/// points' scatter matrix about their mean, as above; any regression text:
/// Cov(b) = s^2 (X^T X)^-1), turned into vehicle axes by the mount yaw
/// (C = R S^-1 R^T), and each angle scatters by s sqrt(C_ii) rad. The
/// design's four dots: pitch 2.9 deg per mm of point scatter (over dots 0
/// and 1, 28 mm apart), roll 2.0 (over dots 2 and 3, 40 mm); without dot 0
/// or 1, pitch 5.0 (over one dot's 14 mm) and roll 2.0; without dot 2 or 3,
/// 3.0 and 3.5. Infinite when the points do not fix a plane.
struct TiltSigma {
  double pitch_deg = 0.0;
  double roll_deg = 0.0;
};
TiltSigma tilt_sigma_deg(const core::Vec3* points, std::size_t count, double point_scatter_mm,
                         double mount_yaw_deg);

/// The scale correction of point 3 above: v = (H / H0) (A / R_zz) v_nominal
/// (vehicle axes, m/s). `ride` must have has_height; without both its pitch
/// and its roll the ground is taken as level (the tilt's share is second
/// order: 0.03 % at 1.5 deg).
void correct_velocity(const core::RideHeight& ride, double nominal_height_mm, double& vx_mps, double& vy_mps);

}  // namespace gvs::dsp
