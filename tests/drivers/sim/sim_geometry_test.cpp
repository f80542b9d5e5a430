// The simulator's image conventions (shared/spec/dataset-format.md): with
// vehicle velocity (vx, vy) a ground point moves by d_row = +vx dt / s,
// d_col = +vy dt / s; mount yaw and yaw rate rotate it as specified.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "gvs/drivers/simulator.hpp"
#include "gvs/core/geometry.hpp"
#include "sim_test_util.hpp"

namespace gvs::drivers::sim::test {
namespace {

constexpr double kDt = 1.0 / 60.0;
constexpr double kMetresPerPx = 0.1e-3;

// The helper itself: a known integer shift made by cropping.
TEST(SimGeometry, ShiftHelperReportsContentMotionDownAndRight) {
  Simulator sim(geometry_config(), constant_motion_scenario(0.0, 0.0));
  const cv::Mat big = render(sim, 0, strobe(0, 20));
  // b(r, c) = a(r - 3, c - 5): content moved 3 rows down and 5 columns right.
  const cv::Mat a = big(cv::Rect(10, 10, 256, 256));
  const cv::Mat b = big(cv::Rect(5, 7, 256, 256));
  const Shift s = measure_shift(a, b);
  EXPECT_NEAR(s.d_row, 3.0, 0.05);
  EXPECT_NEAR(s.d_col, 5.0, 0.05);
}

Shift frame_to_frame(double vx, double vy, double mount_yaw_deg = 0.0, double yaw_rate_dps = 0.0) {
  SimulatorConfig c = geometry_config();
  c.camera.mount_yaw_deg = mount_yaw_deg;
  Simulator sim(c, constant_motion_scenario(vx, vy, yaw_rate_dps));
  // Sharp frames: a 20 us strobe, blur < 0.1 px at these speeds.
  const cv::Mat a = render(sim, 3, strobe(1000, 20));
  const cv::Mat b = render(sim, 4, strobe(1000, 20));
  return measure_shift(a, b);
}

TEST(SimGeometry, ForwardVelocityMovesTextureDown) {
  const double vx = 0.2345;  // 39.08 px per frame
  const Shift s = frame_to_frame(vx, 0.0);
  EXPECT_NEAR(s.d_row, vx * kDt / kMetresPerPx, 0.1);
  EXPECT_NEAR(s.d_col, 0.0, 0.1);
}

TEST(SimGeometry, BackwardVelocityMovesTextureUp) {
  const Shift s = frame_to_frame(-0.1, 0.0);
  EXPECT_NEAR(s.d_row, -0.1 * kDt / kMetresPerPx, 0.1);
  EXPECT_NEAR(s.d_col, 0.0, 0.1);
}

TEST(SimGeometry, LeftwardVelocityMovesTextureRight) {
  const double vy = 0.1567;  // 26.1 px per frame
  const Shift s = frame_to_frame(0.0, vy);
  EXPECT_NEAR(s.d_row, 0.0, 0.1);
  EXPECT_NEAR(s.d_col, vy * kDt / kMetresPerPx, 0.1);
}

TEST(SimGeometry, SubPixelShiftIsExact) {
  // 0.0123 m/s -> 2.05 px per frame: the fraction must come out right.
  const Shift s = frame_to_frame(0.0123, -0.0071);
  EXPECT_NEAR(s.d_row, 0.0123 * kDt / kMetresPerPx, 0.05);
  EXPECT_NEAR(s.d_col, -0.0071 * kDt / kMetresPerPx, 0.05);
}

TEST(SimGeometry, MountYaw90DegreesTurnsForwardMotionLeftInTheImage) {
  // Camera turned 90 deg CCW: vehicle forward is the camera's +y (left), so
  // the ground moves towards the image's left (negative columns).
  const double vx = 0.2;
  const Shift s = frame_to_frame(vx, 0.0, 90.0);
  EXPECT_NEAR(s.d_row, 0.0, 0.1);
  EXPECT_NEAR(s.d_col, -vx * kDt / kMetresPerPx, 0.1);
}

TEST(SimGeometry, MountYaw30DegreesRotatesTheShift) {
  const double vx = 0.2;
  const double vy = 0.05;
  const Shift s = frame_to_frame(vx, vy, 30.0);
  // Camera axes = vehicle axes rotated by -30 deg.
  const double a = -30.0 * std::numbers::pi / 180.0;
  const double cx = std::cos(a) * vx - std::sin(a) * vy;
  const double cy = std::sin(a) * vx + std::cos(a) * vy;
  EXPECT_NEAR(s.d_row, cx * kDt / kMetresPerPx, 0.1);
  EXPECT_NEAR(s.d_col, cy * kDt / kMetresPerPx, 0.1);
  // Same thing through the shared geometry helper.
  core::CameraGeometry cam;
  cam.mount_yaw_deg = 30.0;
  const core::Vec2 expect = core::velocity_to_image_shift({vx, vy}, kDt, cam);
  EXPECT_NEAR(s.d_row, expect.x, 0.1);
  EXPECT_NEAR(s.d_col, expect.y, 0.1);
}

TEST(SimGeometry, YawRateRotatesTextureAboutTheImageCentre) {
  // Standing car turning left (CCW) at 30 deg/s: a ground point at vehicle
  // (x, y) moves by (w y dt, -w x dt), so in the image
  //   d_row = +theta (c - cc),  d_col = -theta (r - rc),  theta = w dt,
  // (the top of the image moves right, the left side up) about the image
  // centre. Fit (t_row, t_col, theta) to the shifts of 15 patches.
  const double theta = 30.0 * std::numbers::pi / 180.0 * kDt;
  Simulator sim(geometry_config(), constant_motion_scenario(0.0, 0.0, 30.0));
  const cv::Mat a = render(sim, 3, strobe(1000, 20));
  const cv::Mat b = render(sim, 4, strobe(1000, 20));
  const int half = 48;
  const double rc = (384 - 1) / 2.0;
  const double cc = (512 - 1) / 2.0;
  double sum_row = 0.0, sum_col = 0.0, num = 0.0, den = 0.0;
  int n = 0;
  for (const double dr : {-120.0, 0.0, 120.0}) {
    for (const double dc : {-180.0, -90.0, 0.0, 90.0, 180.0}) {
      const int r0 = static_cast<int>(rc + dr) - half + 1;
      const int c0 = static_cast<int>(cc + dc) - half + 1;
      const Shift s = measure_shift(a(cv::Rect(c0, r0, 2 * half, 2 * half)),
                                    b(cv::Rect(c0, r0, 2 * half, 2 * half)));
      const double r = r0 + half - 0.5 - rc;  // patch centre relative to the image centre
      const double c = c0 + half - 0.5 - cc;
      sum_row += s.d_row;
      sum_col += s.d_col;
      num += s.d_row * c - s.d_col * r;
      den += c * c + r * r;
      ++n;
    }
  }
  EXPECT_NEAR(num / den, theta, 0.03 * theta);
  EXPECT_NEAR(sum_row / n, 0.0, 0.1);  // rotation centre = image centre (the sensor)
  EXPECT_NEAR(sum_col / n, 0.0, 0.1);
}

}  // namespace
}  // namespace gvs::drivers::sim::test
