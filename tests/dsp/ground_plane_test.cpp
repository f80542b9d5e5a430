// The ground-plane maths of the laser dots (gvs/dsp/ground_plane.hpp) on
// exact and disturbed points: the plane and its attitude from three points
// and from four, a point off it, what one wrong point can hide (the tilt
// doubt), the tilt's scatter for a given point scatter, triangulation, and
// the scale correction.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <random>
#include <string>
#include <tuple>

#include "gvs/core/laser_geometry.hpp"
#include "gvs/dsp/ground_plane.hpp"
#include "gvs/dsp/laser_dots.hpp"

namespace gvs::dsp {
namespace {

constexpr double kNominalMm = 60.0;

TEST(GroundPlane, ExactPointsGiveTheirPlane) {
  // Points on the plane of a known attitude and height (built the way the
  // simulator builds its ground: n = (-sin p, cos p sin r, cos p cos r),
  // n . (P + (0, 0, H)) = 0) must give that attitude and height back.
  for (const auto& [h, pitch, roll] : {std::tuple{60.0, 0.0, 0.0}, std::tuple{57.3, 1.5, -1.0},
                                       std::tuple{71.0, -1.2, 0.8}}) {
    const double th = core::deg_to_rad(pitch), ph = core::deg_to_rad(roll);
    const core::Vec3 n{-std::sin(th), std::cos(th) * std::sin(ph), std::cos(th) * std::cos(ph)};
    auto on_plane = [&](double x, double y) {
      // z from n . (x, y, z + H) = 0
      return core::Vec3{x, y, -(n.x * x + n.y * y) / n.z - h};
    };
    const core::RideHeight r = ground_from_points(on_plane(14, 3), on_plane(-14, -3), on_plane(0, -20), 0.0);
    ASSERT_TRUE(r.has_height && r.has_tilt());
    EXPECT_NEAR(r.height_mm, h, 1e-9);
    EXPECT_NEAR(r.pitch_deg, pitch, 1e-9);
    EXPECT_NEAR(r.roll_deg, roll, 1e-9);
  }
  // Three points in a line fix no plane.
  const core::RideHeight line = ground_from_points({0, 0, -60}, {10, 0, -60}, {20, 0, -60}, 0.0);
  EXPECT_FALSE(line.has_height);
}

TEST(GroundPlane, FourPointsFitTheirPlaneAndShowAPointOffIt) {
  const double h = 58.5, pitch = 1.2, roll = -0.7;
  const double th = core::deg_to_rad(pitch), ph = core::deg_to_rad(roll);
  const core::Vec3 n{-std::sin(th), std::cos(th) * std::sin(ph), std::cos(th) * std::cos(ph)};
  auto on_plane = [&](double x, double y) { return core::Vec3{x, y, -(n.x * x + n.y * y) / n.z - h}; };
  std::array<core::Vec3, 4> p = {on_plane(14, 3), on_plane(-14, -3), on_plane(0, -20), on_plane(0, 20)};
  double residual = -1.0;
  const core::RideHeight r = ground_from_fit(p.data(), 4, 0.0, residual);
  ASSERT_TRUE(r.has_height && r.has_tilt());
  EXPECT_NEAR(r.height_mm, h, 1e-9);
  EXPECT_NEAR(r.pitch_deg, pitch, 1e-9);
  EXPECT_NEAR(r.roll_deg, roll, 1e-9);
  EXPECT_NEAR(residual, 0.0, 1e-9);
  // One point 0.8 mm below its ground: with the design's symmetric dots
  // every residual is a quarter of it (the plane's normal is within 2 deg
  // of vertical, so distances and z differences agree to 0.1 %).
  p[0].z -= 0.8;
  (void)ground_from_fit(p.data(), 4, 0.0, residual);
  EXPECT_NEAR(residual, 0.2, 0.002);
  // Three points: the exact plane, as ground_from_points.
  const core::RideHeight three = ground_from_fit(p.data() + 1, 3, 0.0, residual);
  const core::RideHeight exact = ground_from_points(p[1], p[2], p[3], 0.0);
  EXPECT_NEAR(three.height_mm, exact.height_mm, 1e-9);
  EXPECT_NEAR(three.pitch_deg, exact.pitch_deg, 1e-9);
}

TEST(GroundPlane, TheTiltDoubtBoundsWhatOneWrongPointCanHide) {
  // The design's four points on a tilted plane; each in turn moved off it
  // by e: the tilt the fit then reads is never further from the truth than
  // tilt_doubt_deg of the residual it shows, and for dot 0 or 1 (pitch over
  // 28 mm) the bound is reached.
  const double h = 61.0, pitch = 0.9, roll = 0.4;
  const double th = core::deg_to_rad(pitch), ph = core::deg_to_rad(roll);
  const core::Vec3 n{-std::sin(th), std::cos(th) * std::sin(ph), std::cos(th) * std::cos(ph)};
  auto on_plane = [&](double x, double y) { return core::Vec3{x, y, -(n.x * x + n.y * y) / n.z - h}; };
  const std::array<core::Vec3, 4> truth = {on_plane(14, 3), on_plane(-14, -3), on_plane(0, -20), on_plane(0, 20)};
  for (std::size_t k = 0; k < 4; ++k) {
    for (const double e_mm : {0.06, 0.2, -0.4}) {
      std::array<core::Vec3, 4> p = truth;
      p[k].z += e_mm;
      double residual = 0.0;
      const core::RideHeight r = ground_from_fit(p.data(), 4, 0.0, residual);
      ASSERT_TRUE(r.has_tilt());
      const double tilt_error = std::hypot(r.pitch_deg - pitch, r.roll_deg - roll);
      const double bound = tilt_doubt_deg(p.data(), 4, residual);
      EXPECT_LE(tilt_error, bound * 1.002) << "dot " << k << ", " << e_mm << " mm";
      if (k < 2) {
        EXPECT_NEAR(tilt_error, bound, 0.01 * bound) << "dot " << k << ", " << e_mm << " mm";
      }
      // Height: a quarter of the error, well inside what the height may be off.
      EXPECT_LE(std::abs(r.height_mm - h), std::abs(e_mm) / 4.0 + 1e-3);
    }
  }
  // 8.2 deg per mm of residual for this layout: 0.06 mm is the 0.5 deg the finder allows.
  EXPECT_NEAR(tilt_doubt_deg(truth.data(), 4, 0.06), 0.49, 0.01);
  EXPECT_TRUE(std::isinf(tilt_doubt_deg(truth.data(), 3, 0.0))) << "three points: a wrong one is not seen";
}

TEST(GroundPlane, TheTiltSigmasAreTheScatterOfTheFittedPitchAndRoll) {
  // The design's points on a level plane, each height disturbed by 0.034 mm
  // (a dot's scatter on the procedural asphalt): the fitted pitch's and
  // roll's RMS are tilt_sigma_deg's, for four points and for three, with
  // the head mounted straight and turned by 30 deg.
  const std::array<core::Vec3, 4> design = {core::Vec3{14, 3, -60}, core::Vec3{-14, -3, -60}, core::Vec3{0, -20, -60},
                                            core::Vec3{0, 20, -60}};
  const double scatter_mm = 0.034;
  std::mt19937 rng(7);
  std::normal_distribution<double> noise(0.0, scatter_mm);
  const LaserDotFinder::Thresholds defaults;
  for (const double mount_yaw_deg : {0.0, 30.0}) {
    for (const std::size_t missing : {std::size_t{4}, std::size_t{0}, std::size_t{2}}) {
      std::array<core::Vec3, 4> p{};
      std::size_t n = 0;
      for (std::size_t k = 0; k < 4; ++k)
        if (k != missing) p[n++] = design[k];
      const TiltSigma predicted = tilt_sigma_deg(p.data(), n, scatter_mm, mount_yaw_deg);
      double spp = 0.0, srr = 0.0;
      const int trials = 4000;
      for (int t = 0; t < trials; ++t) {
        std::array<core::Vec3, 4> q = p;
        for (std::size_t k = 0; k < n; ++k) q[k].z += noise(rng);
        double residual = 0.0;
        const core::RideHeight r = ground_from_fit(q.data(), n, mount_yaw_deg, residual);
        ASSERT_TRUE(r.has_tilt());
        spp += r.pitch_deg * r.pitch_deg;
        srr += r.roll_deg * r.roll_deg;
      }
      const std::string where = "without dot " + std::to_string(missing) + ", yaw " + std::to_string(mount_yaw_deg);
      EXPECT_NEAR(std::sqrt(spp / trials), predicted.pitch_deg, 0.05 * predicted.pitch_deg) << where;
      EXPECT_NEAR(std::sqrt(srr / trials), predicted.roll_deg, 0.05 * predicted.roll_deg) << where;
      if (mount_yaw_deg != 0.0) continue;
      // Without dot 0 the pitch (over one dot's 14 mm) is past the finder's
      // bar and the roll (dots 2 and 3, 40 mm apart) within it; four, and
      // three without dot 2, are within it in both.
      EXPECT_EQ(predicted.pitch_deg > defaults.max_tilt_sigma_deg, missing == 0) << where << ": " << predicted.pitch_deg;
      EXPECT_LE(predicted.roll_deg, defaults.max_tilt_sigma_deg) << where;
    }
  }
  const std::array<core::Vec3, 3> line = {core::Vec3{0, 0, -60}, core::Vec3{10, 0, -60}, core::Vec3{20, 0, -60}};
  const TiltSigma in_line = tilt_sigma_deg(line.data(), 3, scatter_mm, 0.0);
  EXPECT_TRUE(std::isinf(in_line.pitch_deg) && std::isinf(in_line.roll_deg));
}

TEST(GroundPlane, TriangulationFindsThePointOnTheBeam) {
  const core::LaserGeometry g = core::design_laser_geometry(core::CameraGeometry{}, kNominalMm);
  for (std::size_t k = 0; k < g.count; ++k) {
    const core::Vec3 truth = g.beams[k].origin_mm() + 47.0 * g.beams[k].direction();
    // The line of sight through the point, scaled arbitrarily.
    const core::Vec3 sight = (-1.0 / truth.z) * truth;
    core::Vec3 p;
    ASSERT_TRUE(triangulate(g.beams[k], sight, p));
    EXPECT_NEAR(p.x, truth.x, 1e-9);
    EXPECT_NEAR(p.y, truth.y, 1e-9);
    EXPECT_NEAR(p.z, truth.z, 1e-9);
  }
}

TEST(GroundPlane, ScaleFollowsTheHeightAndTheTilt) {
  core::RideHeight r;
  r.has_height = true;
  r.height_mm = 66.0;
  double vx = 10.0, vy = -2.0;
  correct_velocity(r, kNominalMm, vx, vy);
  EXPECT_NEAR(vx, 11.0, 1e-12);
  EXPECT_NEAR(vy, -2.2, 1e-12);
  // Pitch alone: the image centre sees ground lengths along x stretched by
  // 1 / cos(pitch), along y unchanged (camera_view.hpp: A = diag(1, cos p), R_zz = cos p).
  r.height_mm = kNominalMm;
  r.has_pitch = r.has_roll = true;
  r.pitch_deg = 1.5;
  vx = 10.0;
  vy = 2.0;
  correct_velocity(r, kNominalMm, vx, vy);
  EXPECT_NEAR(vx, 10.0 / std::cos(core::deg_to_rad(1.5)), 1e-12);
  EXPECT_NEAR(vy, 2.0, 1e-12);
}

}  // namespace
}  // namespace gvs::dsp
