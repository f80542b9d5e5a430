// thesis-orb: ORB frame difference (thesis 4.3, 5.1) on a blob texture
// shifted by known sub-pixel amounts; signs, mount yaw and the real dt.
#include <cmath>
#include <cstdio>
#include <vector>

#include <gtest/gtest.h>

#include "gvs/dsp/vocabulary.hpp"
#include "gvs/dsp/thesis.hpp"
#include "gvs/dsp/thesis_orb_methods.hpp"
#include "thesis_synth.hpp"

namespace gvs::dsp {
namespace {

constexpr int kW = 512;
constexpr int kH = 384;
constexpr std::int64_t kFrameNs = 16'666'667;  // 60 fps

const cv::Mat& texture() {
  static const cv::Mat t = test::blob_texture(kW + 200, kH + 200, 3);
  return t;
}

FrameView view(const cv::Mat& gray, std::int64_t index, std::int64_t t_ns) {
  FrameView f;
  f.gray = gray;
  f.index = index;
  f.t_ns = t_ns;
  f.exposure.exposure_us = 3000.0;
  return f;
}

TEST(ThesisOrb, WrapSafeMeanAngleAndRmsLength) {
  thesis::OrbConfig cfg;
  cfg.min_matches = 2;
  // Two vectors at +179 and -179 deg (camera axes: atan2(d_col, d_row)).
  const double a = deg_to_rad(179.0);
  const std::vector<cv::Point2d> d{{std::cos(a), std::sin(a)}, {std::cos(a) * 3.0, -std::sin(a) * 3.0}};
  const thesis::OrbShift s = thesis::summarise_displacements(d, cfg);
  ASSERT_TRUE(s.ok);
  EXPECT_NEAR(std::abs(s.angle_cam_deg), 180.0, 1e-9);  // a plain mean would say 0
  EXPECT_NEAR(s.rms_px, std::sqrt((1.0 + 9.0) / 2.0), 1e-12);  // eq. 5.2
}

TEST(ThesisOrb, TooFewMatchesIsNotAMeasurement) {
  thesis::OrbConfig cfg;
  const std::vector<cv::Point2d> d{{1.0, 0.0}};
  EXPECT_FALSE(thesis::summarise_displacements(d, cfg).ok);
}

TEST(ThesisOrb, MeasuresKnownSubPixelTextureShift) {
  struct Case {
    double d_row;
    double d_col;
  };
  for (const Case c : {Case{6.3, 0.0}, Case{5.6, 1.7}, Case{4.2, -2.4}, Case{-3.7, 0.6}, Case{0.4, 7.2}}) {
    thesis::OrbFrameDifference orb;
    const thesis::OrbShift s =
        orb.measure(test::shifted_crop(texture(), 0.0, 0.0, kW, kH), test::shifted_crop(texture(), c.d_row, c.d_col, kW, kH));
    ASSERT_TRUE(s.ok);
    std::printf("shift (%.1f, %.1f) px -> (%.2f, %.2f) px, %d matches, quality %.2f\n", c.d_row, c.d_col, s.d_row_px,
                s.d_col_px, s.match_count, s.quality);
    // Keypoints sit on the pixel grid of their pyramid level, so each match is
    // quantised; the mean angle and RMS length come within a few tenths.
    EXPECT_NEAR(s.d_row_px, c.d_row, 0.4);
    EXPECT_NEAR(s.d_col_px, c.d_col, 0.4);
    EXPECT_GT(s.quality, 0.5);
  }
}

// Vehicle velocity -> image shift -> estimator -> vehicle velocity, with the
// real frame interval and a yawed camera.
TEST(ThesisOrb, EstimatorRecoversVelocityWithMountYaw) {
  for (double mount_yaw_deg : {0.0, 30.0, -90.0}) {
    // 0.25 m/s over 1/60 s at 0.1 mm/px is a 42 px texture shift.
    for (const Vec2 v : {Vec2{0.25, 0.0}, Vec2{0.2, 0.05}, Vec2{0.15, -0.07}}) {
      EstimatorConfig cfg;
      cfg.method = "thesis-orb";
      cfg.camera.mount_yaw_deg = mount_yaw_deg;
      const auto est = make_estimator(cfg);
      const double dt_s = static_cast<double>(kFrameNs) * 1e-9;
      const Vec2 shift = velocity_to_image_shift(v, dt_s, cfg.camera);  // (rows, cols)
      const cv::Mat f0 = test::shifted_crop(texture(), 0.0, 0.0, kW, kH);
      const cv::Mat f1 = test::shifted_crop(texture(), shift.x, shift.y, kW, kH);
      const VelocityEstimate e0 = est->estimate(view(f0, 0, 0));
      EXPECT_EQ(e0.method, Method::no_previous);
      EXPECT_EQ(e0.quality, 0.0);
      EXPECT_FALSE(e0.has_speed);
      const VelocityEstimate e1 = est->estimate(view(f1, 1, kFrameNs));
      ASSERT_EQ(e1.method, Method::thesis_orb);
      ASSERT_TRUE(e1.has_speed && e1.has_direction);
      std::printf("yaw %5.1f  v (%.2f, %.2f) -> (%.3f, %.3f) m/s, dir %.2f vs %.2f deg\n", mount_yaw_deg, v.x, v.y,
                  e1.vx_mps, e1.vy_mps, e1.direction_deg, direction_deg(v));
      const double speed = std::hypot(v.x, v.y);
      EXPECT_NEAR(e1.speed_mps, speed, 0.05 * speed);
      EXPECT_NEAR(wrap_deg(e1.direction_deg - direction_deg(v)), 0.0, 3.0);
      EXPECT_EQ(e1.t_ns, kFrameNs + 1'500'000);  // start + light centre (3 ms / 2)
    }
  }
}

TEST(ThesisOrb, SpeedScalesWithTheRealFrameInterval) {
  // Same pixels, twice the interval (a dropped frame): half the speed. The
  // thesis's eq. 5.1 divided by the exposure and would not change.
  EstimatorConfig cfg;
  cfg.method = "thesis-orb";
  const cv::Mat f0 = test::shifted_crop(texture(), 0.0, 0.0, kW, kH);
  const cv::Mat f1 = test::shifted_crop(texture(), 6.0, 0.0, kW, kH);
  const auto a = make_estimator(cfg);
  a->estimate(view(f0, 0, 0));
  const VelocityEstimate one = a->estimate(view(f1, 1, kFrameNs));
  const auto b = make_estimator(cfg);
  b->estimate(view(f0, 0, 0));
  const VelocityEstimate two = b->estimate(view(f1, 2, 2 * kFrameNs));
  ASSERT_TRUE(one.has_speed && two.has_speed);
  EXPECT_NEAR(two.speed_mps, one.speed_mps / 2.0, 1e-9);
  EXPECT_NEAR(one.speed_mps, 6.0 * 1e-4 / (static_cast<double>(kFrameNs) * 1e-9), 0.05 * one.speed_mps);
}

TEST(ThesisOrb, StandingStillGivesZeroSpeed) {
  EstimatorConfig cfg;
  cfg.method = "thesis-orb";
  const auto est = make_estimator(cfg);
  const cv::Mat f = test::shifted_crop(texture(), 0.0, 0.0, kW, kH);
  est->estimate(view(f, 0, 0));
  const VelocityEstimate e = est->estimate(view(f, 1, kFrameNs));
  ASSERT_TRUE(e.has_speed);
  EXPECT_LT(e.speed_mps, VelocityEstimate::kStandstillMps);
  EXPECT_TRUE(e.has_velocity_xy());
}

TEST(ThesisOrb, FlatFrameGivesNoMatch) {
  EstimatorConfig cfg;
  cfg.method = "thesis-orb";
  const auto est = make_estimator(cfg);
  const cv::Mat flat(kH, kW, CV_8UC1, cv::Scalar(100));
  est->estimate(view(flat, 0, 0));
  const VelocityEstimate e = est->estimate(view(flat, 1, kFrameNs));
  EXPECT_EQ(e.method, Method::no_match);
  EXPECT_EQ(e.quality, 0.0);
  EXPECT_FALSE(e.has_speed);
}

}  // namespace
}  // namespace gvs::dsp
