// Laser dots in the simulator (docs/simulator.md, "Laser dots"): where the
// beams meet the ground, lit only while the light is, and nothing changes
// for a head without lasers.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "gvs/core/laser_geometry.hpp"
#include "gvs/drivers/simulator.hpp"
#include "laser_dots.hpp"
#include "sim_test_util.hpp"

namespace gvs::drivers::sim::test {
namespace {

constexpr double kNominalMm = 60.0;

Scenario standing(BodyPose pose) {
  Scenario s = constant_motion_scenario(0.0, 0.0);
  s.body = [pose](double) { return pose; };
  return s;
}

SimulatorConfig with_lasers(double peak = 1.0) {
  SimulatorConfig c = clean_config();
  c.lasers = core::design_laser_geometry(c.camera, kNominalMm);
  c.laser_peak_relative = peak;
  return c;
}

/// Centroid of the positive part of (with - without) / without in a window
/// around (row, col): the dot's own light, the asphalt's reflectance under
/// it divided out (it moves the raw centroid by up to half a pixel, which
/// the finder's tests measure); `sum_out`: the raw sum of with - without, DN.
void centroid(const cv::Mat& with, const cv::Mat& without, double row, double col, int half, double& r_out,
              double& c_out, double& sum_out) {
  double s = 0.0, sr = 0.0, sc = 0.0;
  sum_out = 0.0;
  for (int r = static_cast<int>(row) - half; r <= static_cast<int>(row) + half; ++r) {
    for (int c = static_cast<int>(col) - half; c <= static_cast<int>(col) + half; ++c) {
      if (r < 0 || c < 0 || r >= with.rows || c >= with.cols) continue;
      const double raw = static_cast<double>(with.at<std::uint8_t>(r, c)) - without.at<std::uint8_t>(r, c);
      if (raw <= 0.0) continue;
      sum_out += raw;
      const double d = raw / std::max(1.0, static_cast<double>(without.at<std::uint8_t>(r, c)));
      s += d;
      sr += d * r;
      sc += d * c;
    }
  }
  r_out = s > 0.0 ? sr / s : -1.0;
  c_out = s > 0.0 ? sc / s : -1.0;
}

TEST(SimLasers, DarkLasersLeaveTheFrameAsWithout) {
  // The laser path must not touch the rest of the frame (noise, gain): a
  // laser of zero power renders the frame of a head without lasers, bit for bit.
  const BodyPose pose{2.0, 0.5, -0.3};
  Simulator none(clean_config(), standing(pose));
  Simulator dark(with_lasers(0.0), standing(pose));
  Simulator lit(with_lasers(1.0), standing(pose));
  EXPECT_EQ(cv::norm(render(none, 3, continuous(1000)), render(dark, 3, continuous(1000)), cv::NORM_INF), 0.0);
  EXPECT_GT(cv::norm(render(none, 3, continuous(1000)), render(lit, 3, continuous(1000)), cv::NORM_INF), 50.0);
}

TEST(SimLasers, LevelDotsAreWhereTheBeamsMeetTheGround) {
  // Level ground H below the optical centre: beam k meets it at
  // O + t u with t = (H + z_O) / cos(tilt), seen at row = rc - f x / H,
  // col = cc - f y / H (f = H0 / s0). At 45 deg the dot moves 1 mm on the
  // ground per mm of height: about 10 px.
  const core::CameraGeometry cam;
  const double f = kNominalMm / cam.mm_per_px;
  for (const double heave_mm : {-8.0, 0.0, 6.5}) {
    const BodyPose pose{heave_mm, 0.0, 0.0};
    Simulator none(clean_config(), standing(pose));
    Simulator lit(with_lasers(), standing(pose));
    const cv::Mat a = render(none, 2, continuous(1000));
    const cv::Mat b = render(lit, 2, continuous(1000));
    const core::LaserGeometry g = lit.config().lasers;
    const double h = kNominalMm + heave_mm;
    for (std::size_t k = 0; k < g.count; ++k) {
      const core::LaserBeam& beam = g.beams[k];
      const double t = (h + beam.z_mm) / std::cos(beam.tilt_deg * 3.14159265358979 / 180.0);
      const core::Vec3 p = beam.origin_mm() + t * beam.direction();
      const double row = (cam.height_px - 1) / 2.0 - f * p.x / h;
      const double col = (cam.width_px - 1) / 2.0 - f * p.y / h;
      double r = 0.0, c = 0.0, s = 0.0;
      centroid(b, a, row, col, 9, r, c, s);
      EXPECT_GT(s, 300.0) << "beam " << k << " heave " << heave_mm;
      // Speckle moves the centroid a little.
      EXPECT_NEAR(r, row, 0.4) << "beam " << k << " heave " << heave_mm;
      EXPECT_NEAR(c, col, 0.4) << "beam " << k << " heave " << heave_mm;
    }
  }
}

TEST(SimLasers, DotsAreLitOnlyInThePulses) {
  // The camera rises at 1 m/s: two 20 us pulses 2.9 ms apart see the dots
  // 2.9 mm of height apart (about 29 px), and nothing in between.
  Scenario s = constant_motion_scenario(0.0, 0.0);
  s.body = [](double t) { return BodyPose{1000.0 * t - 30.0, 0.0, 0.0}; };  // 1 mm per ms
  Scenario s2 = s;
  SimulatorConfig c = with_lasers();
  Simulator lit(c, s);
  Simulator none(clean_config(), s2);
  core::ExposurePlan plan;
  plan.exposure_us = 3000.0;
  plan.pulse_count = 2;
  plan.pulses[0] = {0.0, 20.0};
  plan.pulses[1] = {2900.0, 20.0};
  const std::int64_t index = 2;  // t0 = 2 / 60 s
  const cv::Mat a = render(none, index, plan);
  const cv::Mat b = render(lit, index, plan);
  const double t0 = static_cast<double>(index) / c.fps;
  const core::LaserBeam& beam = c.lasers.beams[0];  // moves along the columns
  std::vector<double> cols;
  for (const double t : {t0 + 10e-6, t0 + 2910e-6}) {
    core::Vec3 g;
    double row = 0.0, col = 0.0;
    ASSERT_TRUE(laser_spot(c.camera, kNominalMm, beam, s.body(t), g, row, col));
    double r = 0.0, cc = 0.0, sum = 0.0;
    centroid(b, a, row, col, 6, r, cc, sum);
    EXPECT_GT(sum, 300.0);
    EXPECT_NEAR(cc, col, 0.5);
    cols.push_back(col);
  }
  ASSERT_GT(std::abs(cols[1] - cols[0]), 15.0);
  // Half-way between the two spots the light never was: no dot there.
  core::Vec3 g;
  double row = 0.0, col = 0.0;
  ASSERT_TRUE(laser_spot(c.camera, kNominalMm, beam, s.body(t0 + 1460e-6), g, row, col));
  double r = 0.0, cc = 0.0, sum = 0.0;
  centroid(b, a, row, 0.5 * (cols[0] + cols[1]), 2, r, cc, sum);
  EXPECT_LT(sum, 20.0);
}

TEST(SimLasers, TiltedGroundMovesEachDotAlongItsTrack) {
  // Pitch and roll move the ground under each beam; the dot stays on the
  // beam's image (its track) and moves by the height change under it.
  const core::CameraGeometry cam;
  const BodyPose pose{0.0, 1.5, -1.0};
  Simulator none(clean_config(), standing(pose));
  Simulator lit(with_lasers(), standing(pose));
  const cv::Mat a = render(none, 2, continuous(1000));
  const cv::Mat b = render(lit, 2, continuous(1000));
  const core::LaserGeometry g = lit.config().lasers;
  for (std::size_t k = 0; k < g.count; ++k) {
    core::Vec3 p;
    double row = 0.0, col = 0.0;
    ASSERT_TRUE(laser_spot(cam, kNominalMm, g.beams[k], pose, p, row, col));
    double r = 0.0, c = 0.0, s = 0.0;
    centroid(b, a, row, col, 9, r, c, s);
    EXPECT_NEAR(r, row, 0.4) << "beam " << k;
    EXPECT_NEAR(c, col, 0.4) << "beam " << k;
    // ... and the point is on the tilted plane: height above it along the
    // ground's normal is zero. n = (-sin p, cos p sin r, cos p cos r).
    const double th = 1.5 * 3.14159265358979 / 180.0, ph = -1.0 * 3.14159265358979 / 180.0;
    const core::Vec3 n{-std::sin(th), std::cos(th) * std::sin(ph), std::cos(th) * std::cos(ph)};
    EXPECT_NEAR(core::dot(n, p + core::Vec3{0.0, 0.0, kNominalMm}), 0.0, 1e-9);
  }
}

}  // namespace
}  // namespace gvs::drivers::sim::test
