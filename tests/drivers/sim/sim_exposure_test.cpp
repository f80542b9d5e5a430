// Exposure integration: blur length and direction, the blur is the real
// motion (the average of sharp snapshots along the path), truth and image are
// centred on the middle of the light, pulses give multiple images.
#include <gtest/gtest.h>

#include <cmath>

#include "gvs/drivers/simulator.hpp"
#include "sim_test_util.hpp"

namespace gvs::drivers::sim::test {
namespace {

constexpr double kMetresPerPx = 0.1e-3;

TEST(SimExposure, BlurLengthAlongRowsIsSpeedTimesExposure) {
  // 2 m/s for 3 ms = 6 mm = 60 px.
  Simulator sim(SimulatorConfig{}, constant_motion_scenario(2.0, 0.0));
  const cv::Mat img = render(sim, 2, continuous(3000));
  EXPECT_NEAR(blur_length(img, true, 10, 150), 60.0, 1.5);
  // Nothing of the kind across the motion.
  EXPECT_GT(std::abs(blur_length(img, false, 10, 150) - 60.0), 5.0);
}

TEST(SimExposure, BlurLengthAlongColumnsFollowsLateralSpeedAndExposure) {
  // 1.2 m/s left for 2.5 ms = 3 mm = 30 px.
  SimulatorConfig c;
  c.exposure_us = 2500;
  Simulator sim(c, constant_motion_scenario(0.0, 1.2));
  const cv::Mat img = render(sim, 2, continuous(2500));
  EXPECT_NEAR(blur_length(img, false, 8, 120), 30.0, 1.0);
}

TEST(SimExposure, SharpStrobeHasNoBlur) {
  Simulator sim(clean_config(), constant_motion_scenario(2.0, 0.0));
  const cv::Mat sharp = render(sim, 2, strobe(0, 20));  // 0.4 px
  const cv::Mat blurred = render(sim, 2, continuous(3000));
  // The derivative autocorrelation at the 60 px lag is strongly negative only when blurred.
  const double c_blurred = derivative_autocorrelation(blurred, 60);
  const double c_sharp = derivative_autocorrelation(sharp, 60);
  EXPECT_LT(c_blurred, -0.2) << "sharp: " << c_sharp;
  EXPECT_GT(c_sharp, -0.05) << "blurred: " << c_blurred;
}

/// The continuous exposure must equal the average of sharp snapshots taken
/// along the real path (here with rotation, so every pixel's path is a
/// different arc): prefix-sum path integrals vs. bilinear point samples.
void expect_blur_is_average_of_snapshots(double vx, double vy, double yaw_dps) {
  SimulatorConfig c = clean_config();
  c.sensor.light_falloff = true;
  // Dim enough that no snapshot saturates (clipping each snapshot is not
  // clipping their average: bright sand grains would differ, physically).
  c.sensor.target_mean_dn = 55.0;
  Simulator sim(c, constant_motion_scenario(vx, vy, yaw_dps));
  const cv::Mat blurred = render(sim, 5, continuous(3000));
  cv::Mat sum = cv::Mat::zeros(blurred.size(), CV_64F);
  constexpr int kSnapshots = 150;  // 20 us each, tiling the 3 ms
  for (int k = 0; k < kSnapshots; ++k) {
    cv::Mat f;
    render(sim, 5, strobe(20.0 * k, 20.0)).convertTo(f, CV_64F);
    sum += f;
  }
  cv::Mat mean = sum / kSnapshots;
  cv::Mat b;
  blurred.convertTo(b, CV_64F);
  const cv::Rect inner(8, 8, b.cols - 16, b.rows - 16);
  cv::Scalar mu, sd_blur, sd_diff;
  cv::meanStdDev(b(inner), mu, sd_blur);
  cv::meanStdDev(b(inner) - mean(inner), mu, sd_diff);
  // The snapshots have the same mean grey (auto gain) and 8-bit rounding each.
  EXPECT_LT(sd_diff[0], 0.8) << "blurred frame std " << sd_blur[0];
  EXPECT_GT(sd_blur[0], 5.0);
  // And it is not just any smooth image: a sharp frame differs a lot.
  cv::Mat sharp;
  render(sim, 5, strobe(1490, 20)).convertTo(sharp, CV_64F);
  cv::meanStdDev(b(inner) - sharp(inner), mu, sd_diff);
  EXPECT_GT(sd_diff[0], 5.0);
}

TEST(SimExposure, BlurEqualsAverageOfSnapshotsStraight) { expect_blur_is_average_of_snapshots(1.0, 0.4, 0.0); }

TEST(SimExposure, BlurEqualsAverageOfSnapshotsWhileRotating) {
  // 200 deg/s: corners sweep about 3 px sideways during the exposure.
  expect_blur_is_average_of_snapshots(0.8, -0.3, 200.0);
}

TEST(SimExposure, CoarseRasterAlongLongBlurMatchesTheFineOne) {
  // From 32 px of blur the raster along the motion is at the pixel pitch;
  // it must not change the image (noise-free, 36 px and 60 px of blur, oblique;
  // 8-bit rounding of both alone gives 0.41 DN; measured 0.63 and 0.5 DN RMS
  // against an image standard deviation of 43 DN).
  for (const double v : {1.2, 2.0}) {
    SimulatorConfig fine_cfg = clean_config();
    fine_cfg.coarse_raster_min_blur_px = 0.0;
    SimulatorConfig coarse_cfg = clean_config();
    Simulator fine(fine_cfg, constant_motion_scenario(v * 0.8, v * 0.6));
    Simulator coarse(coarse_cfg, constant_motion_scenario(v * 0.8, v * 0.6));
    SimFrame a, b;
    fine.render(3, continuous(3000), a);
    coarse.render(3, continuous(3000), b);
    EXPECT_GT(fine.last_render_stats().raster_cols, 1.3 * coarse.last_render_stats().raster_cols);
    cv::Mat fa, fb;
    a.gray.convertTo(fa, CV_64F);
    b.gray.convertTo(fb, CV_64F);
    cv::Scalar mu, sd, sd_img;
    cv::meanStdDev(fa - fb, mu, sd);
    cv::meanStdDev(fa, mu, sd_img);
    EXPECT_LT(sd[0], 0.75) << "v = " << v << ", image std " << sd_img[0];
  }
}

TEST(SimExposure, ImageIsCentredOnTheMiddleOfTheLight) {
  // A blurred frame and a sharp snapshot at mid-exposure line up; a snapshot
  // at the exposure start is half a blur length behind.
  Simulator sim(geometry_config(), constant_motion_scenario(1.0, 0.0));
  const cv::Mat blurred = render(sim, 4, continuous(3000));  // 30 px blur
  const cv::Mat mid = render(sim, 4, strobe(1490, 20));
  const cv::Mat start = render(sim, 4, strobe(0, 20));
  EXPECT_NEAR(row_offset(mid, blurred, 40), 0.0, 0.2);
  EXPECT_NEAR(row_offset(start, blurred, 40), 1.0 * 1.49e-3 / kMetresPerPx, 0.3);
}

TEST(SimExposure, TruthIsAtTheMiddleOfTheLight) {
  // vx(t) = 1 + 2 t, so the truth tells when it was taken.
  Scenario ramp{"ramp", 2.0, [](double t) { return BodyMotion{1.0 + 2.0 * t, -0.5, 0.0}; }};
  SimulatorConfig c;
  Simulator sim(c, ramp);
  SimFrame f;
  sim.render(10, continuous(3000), f);
  const std::int64_t start_ns = 166666667;  // 10 / 60 s
  EXPECT_EQ(f.record.index, 10);
  EXPECT_EQ(f.record.t_ns, start_ns);
  EXPECT_EQ(f.truth.t_ns, start_ns + 1500000);
  EXPECT_NEAR(f.truth.vx_mps, 1.0 + 2.0 * (10.0 / 60.0 + 1.5e-3), 1e-9);
  EXPECT_NEAR(f.truth.vy_mps, -0.5, 1e-12);
  EXPECT_NEAR(f.truth.speed_mps, std::hypot(f.truth.vx_mps, -0.5), 1e-12);
  ASSERT_TRUE(f.truth.direction_deg.has_value());
  EXPECT_NEAR(*f.truth.direction_deg, std::atan2(-0.5, f.truth.vx_mps) * 180.0 / 3.14159265358979, 1e-9);

  // Pulses 0:100 and 2000:300: energy centre (50*100 + 2150*300) / 400 = 1625 us.
  core::ExposurePlan p = continuous(3000);
  p.pulse_count = 2;
  p.pulses[0] = {0, 100};
  p.pulses[1] = {2000, 300};
  sim.render(10, p, f);
  EXPECT_EQ(f.truth.t_ns, start_ns + 1625000);
  EXPECT_NEAR(f.truth.vx_mps, 1.0 + 2.0 * (10.0 / 60.0 + 1.625e-3), 1e-9);
  EXPECT_EQ(f.record.exposure.pulse_count, 2U);
}

TEST(SimExposure, NoDirectionWhenStanding) {
  Simulator sim(SimulatorConfig{}, constant_motion_scenario(0.005, 0.0));
  SimFrame f;
  ASSERT_TRUE(sim.next(f));
  EXPECT_FALSE(f.truth.direction_deg.has_value());
  EXPECT_NEAR(f.truth.speed_mps, 0.005, 1e-12);
}

TEST(SimExposure, TwoPulsesMakeADoubleImageAtTheRightSeparation) {
  // 2 m/s, pulses 1500 us apart: images 3 mm = 30 px apart along the rows.
  Simulator sim(geometry_config(), constant_motion_scenario(2.0, 0.0));
  core::ExposurePlan p = continuous(3000);
  p.pulse_count = 2;
  p.pulses[0] = {0, 20};
  p.pulses[1] = {1500, 20};
  const cv::Mat dbl = render(sim, 2, p);
  const cv::Mat single = render(sim, 2, strobe(0, 20));
  double best = -1.0;
  int best_lag = 0;
  for (int lag = 5; lag <= 80; ++lag) {
    const double a = derivative_autocorrelation(dbl, lag);
    if (a > best) {
      best = a;
      best_lag = lag;
    }
  }
  EXPECT_EQ(best_lag, 30);
  EXPECT_GT(best, 0.25);  // 0.5 for a noise-free double image
  EXPECT_LT(std::abs(derivative_autocorrelation(single, 30)), 0.05);
  // Three pulses: echoes at 15 and 30 px.
  p.pulse_count = 3;
  p.pulses[1] = {750, 20};
  p.pulses[2] = {1500, 20};
  const cv::Mat triple = render(sim, 2, p);
  // Noise-free: lag 15 has two of three pairs (2/3), lag 30 one (1/3).
  EXPECT_GT(derivative_autocorrelation(triple, 15), 0.35);
  EXPECT_GT(derivative_autocorrelation(triple, 30), 0.15);
  EXPECT_LT(std::abs(derivative_autocorrelation(triple, 22)), 0.08);
}

TEST(SimExposure, BlurFarLongerThanTheFrameRenders) {
  // 250 km/h for 3 ms = 208 mm = 2083 px of blur, 4x the image width.
  Simulator sim(clean_config(), constant_motion_scenario(250.0 / 3.6, 0.0));
  SimFrame f;
  sim.render(1, continuous(3000), f);
  ASSERT_EQ(f.gray.rows, 384);
  ASSERT_EQ(f.gray.cols, 512);
  // Along the motion the image is nearly constant; across it, streaks remain.
  cv::Mat g;
  f.gray.convertTo(g, CV_64F);
  const cv::Rect inner(100, 80, 312, 224);
  const cv::Mat in = g(inner);
  const cv::Mat d_row = in.rowRange(1, in.rows) - in.rowRange(0, in.rows - 1);
  const cv::Mat d_col = in.colRange(1, in.cols) - in.colRange(0, in.cols - 1);
  const double rms_row = std::sqrt(d_row.dot(d_row) / static_cast<double>(d_row.total()));
  const double rms_col = std::sqrt(d_col.dot(d_col) / static_cast<double>(d_col.total()));
  EXPECT_GT(rms_col, 1.5 * rms_row);
  const double mean = cv::mean(f.gray)[0];
  EXPECT_GT(mean, 60.0);
  EXPECT_LT(mean, 160.0);
  EXPECT_GT(sim.last_render_stats().raster_cols, 2083);  // the raster spans the whole path
}

}  // namespace
}  // namespace gvs::drivers::sim::test
