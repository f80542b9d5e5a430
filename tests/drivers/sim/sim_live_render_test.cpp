// The live fast render (SimulatorConfig::live_fast_render, gvsd's sim:
// camera) against the exact render of the same periodic ground: the frames
// agree within the tolerance docs/simulator.md ("Live source") states.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>

#include <opencv2/core.hpp>

#include "gvs/drivers/simulator.hpp"

namespace gvs::drivers {
namespace {

core::ExposurePlan double_pulse(double pulse_us, double separation_us) {
  core::ExposurePlan p;
  p.pulse_count = 2;
  p.pulses[0] = {0.0, pulse_us};
  p.pulses[1] = {separation_us, pulse_us};
  p.exposure_us = separation_us + pulse_us;
  return p;
}

core::ExposurePlan continuous(double us) {
  core::ExposurePlan p;
  p.exposure_us = us;
  return p;
}

SimulatorConfig live_config(const char* scenario, bool fast) {
  SimulatorConfig c;
  c.scenario = scenario;
  c.loop = true;
  c.periodic_texture = true;
  c.live_fast_render = fast;
  // Noise-free: the frames differ by their rendering only.
  c.sensor.shot_and_read_noise = false;
  c.sensor.fixed_pattern_noise = false;
  return c;
}

struct Agreement {
  double rms_dn = 0.0;          ///< RMS of fast - exact
  double mean_diff_dn = 0.0;    ///< mean of fast - exact
  double contrast_dn = 0.0;     ///< std of the exact frame
  double contrast_ratio = 0.0;  ///< std fast / std exact
  double correlation = 0.0;     ///< of the two frames
  bool box_filtered = false;
};

Agreement compare(const char* scenario, std::int64_t index, const core::ExposurePlan& plan) {
  Simulator exact(live_config(scenario, false));
  Simulator fast(live_config(scenario, true));
  SimFrame a;
  SimFrame b;
  exact.render(index, plan, a);
  fast.render(index, plan, b);
  Agreement g;
  g.box_filtered = fast.last_render_stats().box_filtered;
  cv::Mat fa, fb;
  a.gray.convertTo(fa, CV_64F);
  b.gray.convertTo(fb, CV_64F);
  cv::Scalar ma, sa, mb, sb;
  cv::meanStdDev(fa, ma, sa);
  cv::meanStdDev(fb, mb, sb);
  const cv::Mat d = fb - fa;
  g.rms_dn = std::sqrt(cv::mean(d.mul(d))[0]);
  g.mean_diff_dn = mb[0] - ma[0];
  g.contrast_dn = sa[0];
  g.contrast_ratio = sb[0] / sa[0];
  g.correlation = cv::mean((fa - ma[0]).mul(fb - mb[0]))[0] / (sa[0] * sb[0]);
  std::printf("%s frame %lld, %s: RMS %.2f DN (contrast %.1f DN), mean %+.2f DN, contrast x%.3f, r %.4f, %s\n",
              scenario, static_cast<long long>(index),
              plan.pulse_count ? "double pulse" : "continuous", g.rms_dn, g.contrast_dn, g.mean_diff_dn,
              g.contrast_ratio, g.correlation, g.box_filtered ? "box filters" : "per-pixel integrals");
  return g;
}

TEST(LiveFastRender, DoublePulseFramesAgreeWithTheExactRender) {
  // gvsd's steady plan at 60 km/h: two 12 us pulses (2 px of streak) 600 us apart (100 px).
  for (const std::int64_t index : {30, 150, 300, 420}) {
    const Agreement g = compare("sine", index, double_pulse(12.0, 600.0));
    EXPECT_TRUE(g.box_filtered) << "a translating view takes the box-filter path";
    EXPECT_LE(g.rms_dn, 4.0);
    EXPECT_LE(std::abs(g.mean_diff_dn), 1.0);
    EXPECT_NEAR(g.contrast_ratio, 1.0, 0.05);
    EXPECT_GE(g.correlation, 0.98);
  }
}

TEST(LiveFastRender, LongContinuousExposureAgreesWithTheExactRender) {
  // gvsd's first frames: 3 ms continuous at 60 km/h, 500 px of streak.
  for (const std::int64_t index : {30, 300}) {
    const Agreement g = compare("sine", index, continuous(3000.0));
    EXPECT_LE(g.rms_dn, 2.0);
    EXPECT_LE(std::abs(g.mean_diff_dn), 1.0);
    EXPECT_NEAR(g.contrast_ratio, 1.0, 0.05);
    EXPECT_GE(g.correlation, 0.98);
  }
}

TEST(LiveFastRender, RotatingViewFallsBackToPerPixelIntegralsAndAgrees) {
  // Skidpad: 75 deg/s of yaw turns the view by 0.2 deg in 3 ms, 1 px at the
  // corners: not a translation, so the per-pixel path integrals run (on the
  // pixel-pitch raster).
  const Agreement g = compare("skidpad", 400, continuous(3000.0));
  EXPECT_FALSE(g.box_filtered);
  EXPECT_LE(g.rms_dn, 4.0);
  EXPECT_LE(std::abs(g.mean_diff_dn), 1.0);
  EXPECT_NEAR(g.contrast_ratio, 1.0, 0.05);
  EXPECT_GE(g.correlation, 0.98);
}

TEST(LiveFastRender, IsOnlyUsedWhenAsked) {
  // The exact render stays the default: datasets and accuracy figures use it.
  EXPECT_FALSE(SimulatorConfig{}.live_fast_render);
  Simulator exact(live_config("sine", false));
  Simulator fast(live_config("sine", true));
  SimFrame f;
  exact.render(30, double_pulse(12.0, 600.0), f);
  fast.render(30, double_pulse(12.0, 600.0), f);
  EXPECT_FALSE(exact.last_render_stats().box_filtered);
  // The exact raster is at half the pixel pitch across the motion, the fast one at the pitch.
  EXPECT_GT(exact.last_render_stats().raster_rows, 19 * fast.last_render_stats().raster_rows / 10);
}

}  // namespace
}  // namespace gvs::drivers
