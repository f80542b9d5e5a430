// The laser-dot finder (docs/estimator.md, "Height from the laser dots") on
// simulated frames: height, pitch and roll against the truth; a dot off the
// frame or under dirt left out (no height with fewer than three); dots that
// ran along their tracks within the light; a dark patch; the velocity
// unchanged by the dots once they are masked. Grains taken for dots:
// laser_wrong_dots_test.cpp; the ground-plane maths: ground_plane_test.cpp.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include "gvs/core/laser_geometry.hpp"
#include "gvs/drivers/simulator.hpp"
#include "gvs/dsp/frame_processor.hpp"
#include "gvs/dsp/ground_plane.hpp"
#include "gvs/dsp/laser_dots.hpp"
#include "laser_scene.hpp"

namespace gvs::dsp::laser_test {
namespace {

struct RideErrors {
  int frames = 0, found = 0;
  double h_sq = 0.0, p_sq = 0.0, r_sq = 0.0, h_max = 0.0, tilt_max = 0.0;
};

RideErrors run_finder(drivers::Simulator& sim, const core::ExposurePlan& plan, int frames) {
  LaserDotFinder finder(sim.config().camera, kNominalMm, sim.config().lasers);
  RideErrors e;
  drivers::SimFrame f;
  for (int i = 1; i <= frames; ++i) {
    sim.render(i * 3, plan, f);
    const LaserDotResult res = finder.find(f.gray);
    ++e.frames;
    if (!res.ride.has_height) continue;
    ++e.found;
    const double dh = res.ride.height_mm - f.truth.height_mm.value_or(kNominalMm);
    const double dp = res.ride.pitch_deg - f.truth.pitch_deg.value_or(0.0);
    const double dr = res.ride.roll_deg - f.truth.roll_deg.value_or(0.0);
    e.h_sq += dh * dh;
    e.p_sq += dp * dp;
    e.r_sq += dr * dr;
    e.h_max = std::max(e.h_max, std::abs(dh));
    e.tilt_max = std::max({e.tilt_max, std::abs(dp), std::abs(dr)});
  }
  return e;
}

TEST(LaserDots, HeightPitchAndRollOfSimulatedFrames) {
  // brake with body motion "ride" (heave, pitch under braking, the kerb):
  // double-pulse frames (the asphalt frozen under the dots, the hardest
  // case for the centroid). docs/accuracy.md has the full figures.
  drivers::SimulatorConfig c = laser_config();
  c.scenario = "brake";
  c.body = "ride";
  drivers::Simulator sim(c);
  const RideErrors e = run_finder(sim, double_pulse(), 40);
  ASSERT_GT(e.found, 0);
  const double n = e.found;
  EXPECT_GE(e.found, 0.85 * e.frames) << "coverage";
  EXPECT_LT(std::sqrt(e.h_sq / n), 0.05) << "height RMS, mm";
  EXPECT_LT(std::sqrt(e.p_sq / n), 0.15) << "pitch RMS, deg";
  EXPECT_LT(std::sqrt(e.r_sq / n), 0.15) << "roll RMS, deg";
  // Never a wrong value: no frame off by more than a few RMS.
  EXPECT_LT(e.h_max, 0.15);
  EXPECT_LT(e.tilt_max, 0.5);
}

TEST(LaserDots, AHeadTurnedAboutTheOpticalAxisMeasuresAsTheDesign) {
  // The design's four beams turned by 30 deg about the optical axis: every
  // track runs obliquely across the pixels, so from one sample to the next
  // the spot's sums step diagonally, or not at all, as well as straight.
  drivers::SimulatorConfig c = laser_config();
  c.scenario = "brake";
  c.body = "ride";
  const double turn_deg = 30.0, cos_t = std::cos(core::deg_to_rad(turn_deg)), sin_t = std::sin(core::deg_to_rad(turn_deg));
  for (std::size_t k = 0; k < c.lasers.count; ++k) {
    core::LaserBeam& b = c.lasers.beams[k];
    const double x_mm = b.x_mm, y_mm = b.y_mm;
    b.x_mm = cos_t * x_mm - sin_t * y_mm;
    b.y_mm = sin_t * x_mm + cos_t * y_mm;
    b.azimuth_deg += turn_deg;
  }
  drivers::Simulator sim(c);
  const RideErrors e = run_finder(sim, double_pulse(), 40);
  ASSERT_GT(e.found, 0);
  const double n = e.found;
  EXPECT_GE(e.found, 0.85 * e.frames) << "coverage";
  EXPECT_LT(std::sqrt(e.h_sq / n), 0.05) << "height RMS, mm";
  EXPECT_LT(std::sqrt(e.p_sq / n), 0.15) << "pitch RMS, deg";
  EXPECT_LT(std::sqrt(e.r_sq / n), 0.15) << "roll RMS, deg";
  EXPECT_LT(e.h_max, 0.15);
  EXPECT_LT(e.tilt_max, 0.5);
}

TEST(LaserDots, ADotOffTheFrameLeavesTheOtherThreeOrNoHeight) {
  // Beam 0 moved 30 mm sideways: at the nominal height its dot lands
  // 33 mm left of the centre, outside the 25.6 mm half-width of the view
  // (its track enters the frame above 66 mm).
  drivers::SimulatorConfig c = laser_config();
  c.lasers.beams[0].y_mm += 30.0;
  drivers::Simulator sim(c, standing({0.0, 0.0, 0.0}, 5.0, 0.0));
  LaserDotFinder finder(c.camera, kNominalMm, c.lasers);
  drivers::SimFrame f;
  sim.render(3, double_pulse(), f);
  const LaserDotResult res = finder.find(f.gray);
  EXPECT_FALSE(res.dots[0].found);
  EXPECT_TRUE(res.dots[1].found);
  EXPECT_TRUE(res.dots[2].found);
  EXPECT_TRUE(res.dots[3].found);
  // The other three fix the plane.
  ASSERT_TRUE(res.ride.has_height);
  EXPECT_NEAR(res.ride.height_mm, kNominalMm, 0.1);
  // A head with three beams has no height without all of them ...
  drivers::SimulatorConfig c3 = c;
  c3.lasers.count = 3;
  drivers::Simulator sim3(c3, standing({0.0, 0.0, 0.0}, 5.0, 0.0));
  LaserDotFinder finder3(c3.camera, kNominalMm, c3.lasers);
  sim3.render(3, double_pulse(), f);
  const LaserDotResult res3 = finder3.find(f.gray);
  EXPECT_FALSE(res3.dots[0].found);
  EXPECT_FALSE(res3.ride.has_height);
  EXPECT_FALSE(res3.ride.has_pitch || res3.ride.has_roll);
  // ... and higher up, where its dot is in the frame, the height is back.
  drivers::Simulator high(c3, standing({12.0, 0.0, 0.0}, 5.0, 0.0));
  high.render(3, double_pulse(), f);
  const LaserDotResult up = finder3.find(f.gray);
  ASSERT_TRUE(up.ride.has_height);
  EXPECT_NEAR(up.ride.height_mm, 72.0, 0.1);
}

/// `gray` with a blot of mud (10 % of the light) 3 mm across at (row, col).
cv::Mat with_dirt(const cv::Mat& gray, double row, double col) {
  cv::Mat dirty = gray.clone();
  for (int r = 0; r < dirty.rows; ++r)
    for (int c = 0; c < dirty.cols; ++c)
      if (std::hypot(r - row, c - col) <= 15.0)
        dirty.at<std::uint8_t>(r, c) = static_cast<std::uint8_t>(dirty.at<std::uint8_t>(r, c) / 10);
  return dirty;
}

TEST(LaserDots, DirtOverTwoDotsGivesNoHeight) {
  drivers::SimulatorConfig c = laser_config();
  drivers::Simulator sim(c, standing({1.5, 0.5, -0.3}, 8.0, 1.0));
  LaserDotFinder finder(c.camera, kNominalMm, c.lasers);
  drivers::SimFrame f;
  sim.render(4, double_pulse(), f);
  const LaserDotResult clean = finder.find(f.gray);
  ASSERT_TRUE(clean.ride.has_height) << "the clean frame must measure";
  EXPECT_NEAR(clean.ride.height_mm, 61.5, 0.1);
  // Mud over dot 1: the other three still measure.
  const cv::Mat one = with_dirt(f.gray, clean.dots[1].row, clean.dots[1].col);
  const LaserDotResult res1 = finder.find(one);
  EXPECT_FALSE(res1.dots[1].found);
  ASSERT_TRUE(res1.ride.has_height);
  EXPECT_NEAR(res1.ride.height_mm, 61.5, 0.1);
  // Over dots 1 and 2: two points fix no plane.
  const cv::Mat two = with_dirt(one, clean.dots[2].row, clean.dots[2].col);
  const LaserDotResult res2 = finder.find(two);
  EXPECT_FALSE(res2.dots[2].found);
  EXPECT_FALSE(res2.ride.has_height);
}

TEST(LaserDots, AFaintFourthDotWhereThreeFoundDotsPutItCounts) {
  // Dot 0 dimmed step by step (a dark stone under it): where it no longer
  // stands step 2's 4 robust sigmas above its track, it is still looked
  // for where dots 1-3 put it, with min_sigmas_where_put (3) there. So the
  // plane keeps its four dots, and its pitch, over a range of dimming where
  // the bar of step 2 would leave three (height and roll only); a dot
  // blotted out is not made up.
  LevelScene scene;
  auto& [c, f, finder, clean] = scene;
  ASSERT_EQ(clean.found, 4U);
  ASSERT_TRUE(clean.ride.has_tilt());
  LaserDotFinder step2_bar(c.camera, kNominalMm, c.lasers);
  LaserDotFinder::Thresholds t = step2_bar.thresholds();
  t.min_sigmas_where_put = t.min_sigmas;
  step2_bar.set_thresholds(t);
  int kept_only_by_the_lower_bar = 0;
  for (int step = 30; step >= 0; --step) {
    const double gain = 0.01 * step;
    const cv::Mat dim = with_grains(f.gray, {}, {&clean.dots[0]}, gain, clean.dots[0].mask_background_dn);
    const LaserDotResult res = finder.find(dim);
    const LaserDotResult old = step2_bar.find(dim);
    ASSERT_TRUE(res.ride.has_height) << "gain " << gain;
    EXPECT_NEAR(res.ride.height_mm, clean.ride.height_mm, 0.05) << "gain " << gain;
    if (res.ride.has_pitch) {
      EXPECT_EQ(res.found, 4U) << "gain " << gain;
      EXPECT_NEAR(res.ride.pitch_deg, clean.ride.pitch_deg, 0.2) << "gain " << gain;
      EXPECT_NEAR(res.dots[0].row, clean.dots[0].row, 1.0) << "gain " << gain;
      EXPECT_NEAR(res.dots[0].col, clean.dots[0].col, 1.0) << "gain " << gain;
    }
    EXPECT_TRUE(res.ride.has_pitch || !old.ride.has_pitch) << "gain " << gain << ": the lower bar loses a pitch";
    if (res.ride.has_pitch && !old.ride.has_pitch) ++kept_only_by_the_lower_bar;
    if (step == 0) {
      EXPECT_FALSE(res.ride.has_pitch) << "blotted out: three dots";
    }
  }
  EXPECT_GE(kept_only_by_the_lower_bar, 2);
}

TEST(LaserDots, DotsThatRanAlongTheirTracksWithinTheLightKeepTheHeightNotTheTilt) {
  // The body rising at 90 mm/s (9 px per 16.7 ms along each track) under a
  // double pulse whose pulses are 6.6 ms apart: each dot is imaged twice,
  // 6 px apart (4 spot sigmas), and the centroid may settle on either. The
  // frames keep their height; their tilt goes out only where the light is
  // short enough (0.33 ms between the pulses: 0.3 px).
  drivers::SimulatorConfig c = laser_config();
  drivers::sim::Scenario rising = drivers::sim::constant_motion_scenario(2.0, 0.0);
  rising.body = [](double t_s) { return drivers::sim::BodyPose{60.0 * t_s - 2.0, 0.0, 0.0}; };
  core::ExposurePlan long_pulses;
  long_pulses.pulse_count = 2;
  long_pulses.pulses[0] = {0.0, 20.0};
  long_pulses.pulses[1] = {6600.0, 20.0};
  long_pulses.exposure_us = 6620.0;
  for (const core::ExposurePlan& plan : {long_pulses, double_pulse()}) {
    drivers::Simulator sim(c, rising);
    LaserDotFinder finder(c.camera, kNominalMm, c.lasers);
    drivers::SimFrame f;
    int with_height = 0, with_an_angle = 0, with_both = 0;
    for (int i = 0; i < 4; ++i) {
      sim.render(i, plan, f);
      const LaserDotResult res = finder.find(f.gray, core::mid_exposure_ns(f.record.t_ns, plan), plan.exposure_us);
      if (i == 0 || !res.ride.has_height) continue;  // the first frame: nothing to tell the rate by
      ++with_height;
      EXPECT_NEAR(res.ride.height_mm, f.truth.height_mm.value_or(kNominalMm), 0.15) << "frame " << i;
      if (res.ride.has_pitch || res.ride.has_roll) ++with_an_angle;
      if (res.ride.has_tilt()) ++with_both;
    }
    EXPECT_GE(with_height, 2) << plan.exposure_us << " us";
    if (plan.exposure_us > 1000.0) {
      EXPECT_EQ(with_an_angle, 0) << "dots imaged twice, 6 px apart";
    } else {
      EXPECT_EQ(with_both, with_height) << "0.3 px apart";
    }
  }
}

TEST(LaserDots, ADarkPatchGivesTheHeightOrNone) {
  // A dark patch of asphalt under every dot (30 % of the light, dots
  // included: the laser lights it as dimly): either the dots are still
  // found and the height is right, or there is none; never a wrong value.
  drivers::SimulatorConfig c = laser_config();
  drivers::Simulator sim(c, standing({-2.0, 0.0, 0.0}, 8.0, 0.0));
  LaserDotFinder finder(c.camera, kNominalMm, c.lasers);
  drivers::SimFrame f;
  for (const double dim : {0.3, 0.15, 0.05}) {
    sim.render(4, double_pulse(), f);
    cv::Mat dark = f.gray.clone();
    dark.convertTo(dark, CV_8UC1, dim, 0.0);
    const LaserDotResult res = finder.find(dark);
    if (res.ride.has_height) {
      EXPECT_NEAR(res.ride.height_mm, 58.0, 0.15) << "dim " << dim;
    }
    if (dim == 0.05) {
      EXPECT_FALSE(res.ride.has_height) << "5 % of the light leaves nothing to measure";
    }
  }
}

TEST(LaserDots, MaskedDotsLeaveTheVelocityAsWithout) {
  // The same run with and without lasers (same asphalt, same noise): the
  // masked dots must not change the estimator's velocity beyond what the
  // scale correction does at the nominal height (flat body: H = H0).
  drivers::SimulatorConfig with = laser_config(9);
  drivers::SimulatorConfig without = with;
  without.lasers = core::LaserGeometry{};
  const auto scenario = drivers::sim::constant_motion_scenario(12.0, 1.5, 0.0, 2.0);
  drivers::Simulator sim_with(with, scenario);
  drivers::Simulator sim_without(without, scenario);
  FrameProcessorConfig pc_with;
  pc_with.estimator.camera = with.camera;
  pc_with.lasers = with.lasers;
  FrameProcessorConfig pc_without = pc_with;
  pc_without.lasers = core::LaserGeometry{};
  FrameProcessor p_with(pc_with), p_without(pc_without);
  drivers::SimFrame a, b;
  int compared = 0, scaled = 0;
  double diff_sq = 0.0, dir_diff_max = 0.0;
  for (std::int64_t i = 0; i < 40; ++i) {
    sim_with.render(i, double_pulse(), a);
    sim_without.render(i, double_pulse(), b);
    const core::VelocityEstimate ea = p_with.process({a.gray, a.record.index, a.record.t_ns, a.record.exposure});
    const core::VelocityEstimate eb = p_without.process({b.gray, b.record.index, b.record.t_ns, b.record.exposure});
    if (ea.scale_source == core::ScaleSource::laser_dots) ++scaled;
    EXPECT_EQ(eb.scale_source, core::ScaleSource::nominal);
    if (!(ea.has_speed && eb.has_speed && ea.has_direction && eb.has_direction)) continue;
    ++compared;
    const double d = (ea.speed_mps - eb.speed_mps) / eb.speed_mps;
    diff_sq += d * d;
    dir_diff_max = std::max(dir_diff_max, std::abs(ea.direction_deg - eb.direction_deg));
  }
  ASSERT_GE(compared, 30);
  EXPECT_GE(scaled, 30);
  // The dots' height error (about 0.02 mm in 60 mm, 0.04 %) and the masked
  // 0.5 % of the frame: well within the double pulse's 0.25 % target.
  EXPECT_LT(std::sqrt(diff_sq / compared) * 100.0, 0.15);
  EXPECT_LT(dir_diff_max, 0.1);
}

}  // namespace
}  // namespace gvs::dsp::laser_test
