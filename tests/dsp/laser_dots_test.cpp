// The laser-dot finder (docs/estimator.md, "Height from the laser dots") on
// simulated frames: height, pitch and roll against the truth; a dot off the
// frame or under dirt left out (no height with fewer than three); a bright
// grain on a track refused by the fourth dot, and the fourth found where three
// put it under a brighter grain; a standing car's dots where they brightened
// since the last frame; the velocity unchanged by the
// dots once they are masked. The ground-plane maths: ground_plane_test.cpp.
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

namespace gvs::dsp {
namespace {

constexpr double kNominalMm = 60.0;

drivers::SimulatorConfig laser_config(std::uint64_t seed = 5) {
  drivers::SimulatorConfig c;
  c.seed = seed;
  c.lasers = core::design_laser_geometry(c.camera, kNominalMm);
  return c;
}

drivers::sim::Scenario standing(drivers::sim::BodyPose pose, double vx_mps = 0.0, double vy_mps = 0.0) {
  drivers::sim::Scenario s = drivers::sim::constant_motion_scenario(vx_mps, vy_mps);
  s.body = [pose](double) { return pose; };
  return s;
}

core::ExposurePlan double_pulse() {
  core::ExposurePlan p;
  p.exposure_us = 340.0;
  p.pulse_count = 2;
  p.pulses[0] = {0.0, 6.667};
  p.pulses[1] = {333.333, 6.667};
  return p;
}

/// Frame 4 of a double pulse at 8 m/s, the body level at the nominal height.
drivers::SimFrame level_frame(const drivers::SimulatorConfig& c) {
  drivers::Simulator sim(c, standing({0.0, 0.0, 0.0}, 8.0, 0.0));
  drivers::SimFrame f;
  sim.render(4, double_pulse(), f);
  return f;
}

/// The design's head over level ground (level_frame), a finder for its
/// four beams, and what that finds on the frame as rendered.
struct LevelScene {
  drivers::SimulatorConfig c = laser_config();
  drivers::SimFrame f = level_frame(c);
  LaserDotFinder finder{c.camera, kNominalMm, c.lasers};
  LaserDotResult clean = finder.find(f.gray);
};

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
  EXPECT_FALSE(res3.ride.has_tilt);
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

/// The point `shift_px` from dot `k` along its track, towards a higher ground.
void along_track(const drivers::SimulatorConfig& c, const LaserDot& dot, std::size_t k, double shift_px, double& row,
                 double& col) {
  double r_hi = 0.0, c_hi = 0.0;
  const core::LaserBeam& b = c.lasers.beams[k];
  core::head_to_pixel(c.camera, kNominalMm, b.origin_mm() + ((kNominalMm + 5.0 + b.z_mm) / -b.direction().z) * b.direction(),
                      r_hi, c_hi);
  const double len = std::hypot(r_hi - dot.row, c_hi - dot.col);
  row = dot.row + shift_px * (r_hi - dot.row) / len;
  col = dot.col + shift_px * (c_hi - dot.col) / len;
}

/// The frame with dot `k` blotted out and a spot as bright painted on its
/// track `shift_px` further along (towards a higher ground): a grain the
/// finder takes for the dot.
cv::Mat with_grain_for_dot(const drivers::SimulatorConfig& c, const cv::Mat& gray, const LaserDot& dot, std::size_t k,
                           double shift_px) {
  double row = 0.0, col = 0.0;
  along_track(c, dot, k, shift_px, row, col);
  cv::Mat out = gray.clone();
  const double background = dot.mask_background_dn;
  const double peak =
      gray.at<std::uint8_t>(static_cast<int>(std::lround(dot.row)), static_cast<int>(std::lround(dot.col))) - background;
  for (int r = 0; r < out.rows; ++r) {
    for (int cc = 0; cc < out.cols; ++cc) {
      const double d_dot = std::hypot(r - dot.row, cc - dot.col);
      const double d_grain = std::hypot(r - row, cc - col);
      double v = out.at<std::uint8_t>(r, cc);
      if (d_dot <= 4.0) v = background;                                                      // the dot, gone
      if (d_grain <= 4.0) v = background + peak * std::exp(-0.5 * d_grain * d_grain / 1.44);  // the grain
      out.at<std::uint8_t>(r, cc) = static_cast<std::uint8_t>(std::clamp(std::lround(v), 0L, 255L));
    }
  }
  return out;
}

TEST(LaserDots, TheFourthDotRefusesABrightGrainTakenForADot) {
  LevelScene scene;
  auto& [c, f, finder, clean] = scene;
  core::LaserGeometry three = c.lasers;
  three.count = 3;
  LaserDotFinder finder3(c.camera, kNominalMm, three);
  ASSERT_TRUE(clean.dots[0].found && clean.ride.has_height);

  // 6 px along (0.6 mm of height on that beam alone): three beams make a
  // plausible plane of it and a wrong height; four do not agree on a plane,
  // and since the design's dots are symmetric (each set of three leaves the
  // fourth equally far off) they cannot tell which is wrong: no height.
  const cv::Mat near = with_grain_for_dot(c, f.gray, clean.dots[0], 0, 6.0);
  const LaserDotResult res3 = finder3.find(near);
  ASSERT_TRUE(res3.ride.has_height) << "the grain must pass for the dot, or the test shows nothing";
  EXPECT_GT(std::abs(res3.ride.height_mm - kNominalMm), 0.15);
  const LaserDotResult four = finder.find(near);
  EXPECT_EQ(four.found, 4U);
  EXPECT_FALSE(four.ride.has_height);
  EXPECT_FALSE(four.ride.has_tilt);

  // 40 px along: a plane through the grain tilts beyond any car's pitch, so
  // only the other three make a ground, and they measure it.
  const cv::Mat far = with_grain_for_dot(c, f.gray, clean.dots[0], 0, 40.0);
  const LaserDotResult res_far = finder.find(far);
  EXPECT_FALSE(res_far.dots[0].found);
  EXPECT_EQ(res_far.dots[0].status, DotStatus::off_plane);
  ASSERT_TRUE(res_far.ride.has_height);
  EXPECT_NEAR(res_far.ride.height_mm, kNominalMm, 0.1);
  EXPECT_FALSE(finder3.find(far).ride.has_height);
}

/// `gray` with white grains (255, 2 px, a ring of `background` around) at
/// `grains` and the dots within 5 px of `dimmed` dimmed to `gain` of their
/// contrast over `background`.
cv::Mat with_grains(const cv::Mat& gray, const std::vector<std::array<double, 2>>& grains,
                    const std::vector<const LaserDot*>& dimmed, double gain, double background) {
  cv::Mat out = gray.clone();
  for (int r = 0; r < out.rows; ++r) {
    for (int cc = 0; cc < out.cols; ++cc) {
      double v = out.at<std::uint8_t>(r, cc);
      for (const LaserDot* d : dimmed)
        if (std::hypot(r - d->row, cc - d->col) <= 5.0) v = background + (v - background) * gain;
      for (const auto& [gr, gc] : grains) {
        const double d_grain = std::hypot(r - gr, cc - gc);
        if (d_grain <= 2.0) v = 255.0;
        else if (d_grain <= 5.0) v = background;
      }
      out.at<std::uint8_t>(r, cc) = static_cast<std::uint8_t>(std::clamp(std::lround(v), 0L, 255L));
    }
  }
  return out;
}

/// `gray` with the spot of dot `k` scaled by `dot_gain` over its ground and
/// a white grain (a 2 px disc at 255 on the dot's ground) on its track
/// `shift_px` further along.
cv::Mat with_grain_on_track(const drivers::SimulatorConfig& c, const cv::Mat& gray, const LaserDot& dot, std::size_t k,
                            double shift_px, double dot_gain) {
  std::array<double, 2> grain{};
  along_track(c, dot, k, shift_px, grain[0], grain[1]);
  return with_grains(gray, {grain}, {&dot}, dot_gain, dot.mask_background_dn);
}

TEST(LaserDots, FourDotsThatDisagreeEnoughToHideAWrongTiltKeepTheHeightOnly) {
  // Dot 0 blotted out (a dark stone) and a white grain on its track a few
  // pixels further: taken for the dot, it sits 0.35 mm off the ground. The
  // four still agree within max_plane_residual_mm (a quarter of it each),
  // so the height stands (a quarter off); the pitch, resting on dots 0 and 1,
  // would be 0.7 deg off, which the residual cannot rule out: no tilt.
  LevelScene scene;
  auto& [c, f, finder, clean] = scene;
  ASSERT_EQ(clean.found, 4U);
  ASSERT_TRUE(clean.ride.has_tilt);
  LaserDotFinder::Thresholds no_doubt = finder.thresholds();
  no_doubt.max_tilt_doubt_deg = 90.0;
  LaserDotFinder trusting(c.camera, kNominalMm, c.lasers);
  trusting.set_thresholds(no_doubt);
  for (const double shift_px : {1.0, 3.5}) {
    const cv::Mat moved = with_grain_on_track(c, f.gray, clean.dots[0], 0, shift_px, 0.0);
    const LaserDotResult res = finder.find(moved);
    const LaserDotResult trusted = trusting.find(moved);
    ASSERT_EQ(res.found, 4U) << shift_px << " px";
    ASSERT_TRUE(res.ride.has_height) << shift_px << " px";
    EXPECT_NEAR(res.ride.height_mm, clean.ride.height_mm, 0.15) << shift_px << " px";
    ASSERT_TRUE(trusted.ride.has_tilt);
    if (shift_px < 2.0) {
      EXPECT_TRUE(res.ride.has_tilt) << "a dot 0.1 mm off hides at most 0.2 deg";
    } else {
      EXPECT_GT(std::abs(trusted.ride.pitch_deg - clean.ride.pitch_deg), 0.5) << "the tilt it would have sent";
      EXPECT_FALSE(res.ride.has_tilt) << "pitch " << trusted.ride.pitch_deg << " against " << clean.ride.pitch_deg;
    }
  }
}

TEST(LaserDots, TheFourthDotIsFoundWhereTheOtherThreePutItUnderABrighterGrain) {
  // Two tracks in trouble: a white grain outshines dot 3 (dimmed to half,
  // on a darker stone) 40 px along its track, and another as bright as
  // dot 1 stands 40 px along its own. Every plane of the brightest spots
  // fails, and dots 0-2 with dot 1's rival beside it make a plane nothing
  // checks; the plane of dots 0-2 puts dot 3 where it is, and its track
  // shows it there: four dots, one plane, the right height.
  LevelScene scene;
  auto& [c, f, finder, clean] = scene;
  ASSERT_EQ(clean.found, 4U);
  ASSERT_TRUE(clean.ride.has_height);
  const cv::Mat grain3 = with_grain_on_track(c, f.gray, clean.dots[3], 3, 40.0, 0.5);
  const cv::Mat both = with_grain_on_track(c, grain3, clean.dots[1], 1, 40.0, 1.0);
  const LaserDotResult res = finder.find(both);
  ASSERT_TRUE(res.ride.has_height) << "dot 3 " << static_cast<int>(res.dots[3].status) << " dot 1 "
                                   << static_cast<int>(res.dots[1].status);
  EXPECT_NEAR(res.ride.height_mm, clean.ride.height_mm, 0.05);
  EXPECT_NEAR(res.ride.pitch_deg, clean.ride.pitch_deg, 0.2);
  EXPECT_NEAR(res.ride.roll_deg, clean.ride.roll_deg, 0.2);
  EXPECT_EQ(res.found, 4U);
  EXPECT_NEAR(res.dots[3].row, clean.dots[3].row, 0.5);
  EXPECT_NEAR(res.dots[3].col, clean.dots[3].col, 0.5);
  // Both spots on track 3 are masked: the dot, and the grain taken for it.
  EXPECT_TRUE(res.dots[3].masked && res.dots[3].rival);
  EXPECT_NEAR(res.dots[3].mask_row, clean.dots[3].row, 0.5);
  EXPECT_GT(std::hypot(res.dots[3].rival_row - clean.dots[3].row, res.dots[3].rival_col - clean.dots[3].col), 30.0);

  // Without the dot under the grain's track (blotted out), nothing stands
  // where the three put it: no height rather than an unchecked plane.
  cv::Mat blotted = both.clone();
  for (int r = 0; r < blotted.rows; ++r)
    for (int cc = 0; cc < blotted.cols; ++cc)
      if (std::hypot(r - clean.dots[3].row, cc - clean.dots[3].col) <= 5.0)
        blotted.at<std::uint8_t>(r, cc) = static_cast<std::uint8_t>(std::lround(clean.dots[3].mask_background_dn));
  EXPECT_FALSE(finder.find(blotted).ride.has_height);
}

TEST(LaserDots, ThreeDotsWithoutDotZeroOrOneKeepTheHeightNotTheTilt) {
  // Dot 0 not seen (blotted out): the pitch then rests on dot 1 alone
  // against the x = 0 line of dots 2 and 3 (1.7 times the four dots'
  // scatter), nothing checks it, and the frame keeps its height only.
  // Without dot 2 the pitch rests on dots 0 and 1 and the tilt goes out.
  LevelScene scene;
  auto& [c, f, finder, clean] = scene;
  ASSERT_EQ(clean.found, 4U);
  ASSERT_TRUE(clean.ride.has_tilt);
  auto without = [&](std::size_t k) {
    cv::Mat blotted = f.gray.clone();
    const LaserDot& d = clean.dots[k];
    for (int r = 0; r < blotted.rows; ++r)
      for (int cc = 0; cc < blotted.cols; ++cc)
        if (std::hypot(r - d.row, cc - d.col) <= 5.0)
          blotted.at<std::uint8_t>(r, cc) = static_cast<std::uint8_t>(std::lround(d.mask_background_dn));
    return blotted;
  };
  const LaserDotResult no0 = finder.find(without(0));
  EXPECT_EQ(no0.found, 3U);
  ASSERT_TRUE(no0.ride.has_height);
  EXPECT_NEAR(no0.ride.height_mm, clean.ride.height_mm, 0.1);
  EXPECT_FALSE(no0.ride.has_tilt);
  const LaserDotResult no2 = finder.find(without(2));
  EXPECT_EQ(no2.found, 3U);
  ASSERT_TRUE(no2.ride.has_height);
  EXPECT_TRUE(no2.ride.has_tilt);
  EXPECT_NEAR(no2.ride.pitch_deg, clean.ride.pitch_deg, 0.2);
}

TEST(LaserDots, GrainsOutshiningOneDotDoNotHideItFromTheOtherThree) {
  // Dot 0 dimmed to half (a darker stone) under a white grain 40 px along
  // its track: the grain is taken for the dot, misses the plane of the
  // other three, and the plane they make puts dot 0 where it is: four dots.
  // With a second grain 40 px the other way the track is contested by two
  // grains, neither on the plane: the dot, a third spot, is found the same.
  LevelScene scene;
  auto& [c, f, finder, clean] = scene;
  ASSERT_EQ(clean.found, 4U);
  const cv::Mat one = with_grain_on_track(c, f.gray, clean.dots[0], 0, 40.0, 0.5);
  std::array<double, 2> other{};
  along_track(c, clean.dots[0], 0, -40.0, other[0], other[1]);
  const cv::Mat two = with_grains(one, {other}, {}, 1.0, clean.dots[0].mask_background_dn);
  for (const cv::Mat* frame : {&one, &two}) {
    const LaserDotResult res = finder.find(*frame);
    EXPECT_EQ(res.found, 4U) << (frame == &one ? "one grain" : "two grains") << ", dot 0 "
                             << static_cast<int>(res.dots[0].status);
    ASSERT_TRUE(res.ride.has_height && res.ride.has_tilt);
    EXPECT_NEAR(res.dots[0].row, clean.dots[0].row, 0.5);
    EXPECT_NEAR(res.dots[0].col, clean.dots[0].col, 0.5);
    EXPECT_NEAR(res.ride.height_mm, clean.ride.height_mm, 0.05);
    EXPECT_NEAR(res.ride.pitch_deg, clean.ride.pitch_deg, 0.2);
    // The dot is masked where it is.
    EXPECT_NEAR(res.dots[0].mask_row, clean.dots[0].row, 0.5);
    EXPECT_NEAR(res.dots[0].mask_col, clean.dots[0].col, 0.5);
  }
}

TEST(LaserDots, AStandingCarsDotsAreFoundWhereTheyBrightenedMovedTogetherFromTheLastPlane) {
  // A standing car over white grains on tracks 1 and 3, 40 px along them
  // from the dots, in both frames (the ground does not move). In the first
  // frame dot 3 lies on a darker stone (half its contrast): the fourth dot
  // where three put it resolves it. Then the body rises by 0.6 mm (the dots
  // move about 6 px along their tracks) and dot 1 lands on a darker stone
  // too: no plane of the frame's own spots holds (the frame alone gives no
  // height), but in the sequence the four dots are where the frame
  // brightened, moved together from the last plane: the right height.
  drivers::SimulatorConfig c = laser_config();
  const core::ExposurePlan plan = double_pulse();
  drivers::SimFrame f0;
  drivers::SimFrame f1;
  drivers::Simulator(c, standing({0.0, 0.0, 0.0})).render(4, plan, f0);
  drivers::Simulator(c, standing({0.6, 0.0, 0.0})).render(5, plan, f1);
  LaserDotFinder alone(c.camera, kNominalMm, c.lasers);
  const LaserDotResult clean0 = alone.find(f0.gray);
  const LaserDotResult clean1 = alone.find(f1.gray);
  ASSERT_EQ(clean0.found, 4U);
  ASSERT_EQ(clean1.found, 4U);
  ASSERT_NEAR(clean1.ride.height_mm - clean0.ride.height_mm, 0.6, 0.05);
  std::vector<std::array<double, 2>> grains;
  for (const std::size_t k : {std::size_t{1}, std::size_t{3}}) {
    std::array<double, 2> g{};
    along_track(c, clean0.dots[k], k, 40.0, g[0], g[1]);
    grains.push_back(g);
  }
  const double background = clean0.dots[3].mask_background_dn;
  const cv::Mat frame0 = with_grains(f0.gray, grains, {&clean0.dots[3]}, 0.5, background);
  const cv::Mat frame1 = with_grains(f1.gray, grains, {&clean1.dots[1], &clean1.dots[3]}, 0.5, background);
  ASSERT_FALSE(alone.find(frame1).ride.has_height);

  LaserDotFinder finder(c.camera, kNominalMm, c.lasers);
  const auto t_mid = [&](const drivers::SimFrame& f) { return core::mid_exposure_ns(f.record.t_ns, plan); };
  const LaserDotResult first = finder.find(frame0, t_mid(f0), plan.exposure_us);
  ASSERT_TRUE(first.ride.has_height);
  EXPECT_NEAR(first.ride.height_mm, clean0.ride.height_mm, 0.05);
  const LaserDotResult res = finder.find(frame1, t_mid(f1), plan.exposure_us);
  ASSERT_TRUE(res.ride.has_height);
  EXPECT_EQ(res.found, 4U);
  EXPECT_NEAR(res.ride.height_mm, clean1.ride.height_mm, 0.05);
  EXPECT_NEAR(res.ride.pitch_deg, clean1.ride.pitch_deg, 0.2);
  EXPECT_NEAR(res.ride.roll_deg, clean1.ride.roll_deg, 0.2);
  for (const std::size_t k : {std::size_t{1}, std::size_t{3}}) {
    EXPECT_NEAR(res.dots[k].row, clean1.dots[k].row, 0.5) << "dot " << k;
    EXPECT_NEAR(res.dots[k].col, clean1.dots[k].col, 0.5) << "dot " << k;
    // The grain step 2 took for the dot stays masked beside it.
    EXPECT_TRUE(res.dots[k].masked && res.dots[k].rival) << "dot " << k;
  }

  // Too late for the last plane (max_prior_age_s), or after forget(): the
  // frame on its own again.
  LaserDotFinder late(c.camera, kNominalMm, c.lasers);
  ASSERT_TRUE(late.find(frame0, t_mid(f0), plan.exposure_us).ride.has_height);
  EXPECT_FALSE(late.find(frame1, t_mid(f0) + 200'000'000, plan.exposure_us).ride.has_height);
  LaserDotFinder forgetful(c.camera, kNominalMm, c.lasers);
  ASSERT_TRUE(forgetful.find(frame0, t_mid(f0), plan.exposure_us).ride.has_height);
  forgetful.forget();
  EXPECT_FALSE(forgetful.find(frame1, t_mid(f1), plan.exposure_us).ride.has_height);
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
    int with_height = 0, with_tilt = 0;
    for (int i = 0; i < 4; ++i) {
      sim.render(i, plan, f);
      const LaserDotResult res = finder.find(f.gray, core::mid_exposure_ns(f.record.t_ns, plan), plan.exposure_us);
      if (i == 0 || !res.ride.has_height) continue;  // the first frame: nothing to tell the rate by
      ++with_height;
      EXPECT_NEAR(res.ride.height_mm, f.truth.height_mm.value_or(kNominalMm), 0.15) << "frame " << i;
      if (res.ride.has_tilt) ++with_tilt;
    }
    EXPECT_GE(with_height, 2) << plan.exposure_us << " us";
    if (plan.exposure_us > 1000.0) {
      EXPECT_EQ(with_tilt, 0) << "dots imaged twice, 6 px apart";
    } else {
      EXPECT_EQ(with_tilt, with_height) << "0.3 px apart";
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
}  // namespace gvs::dsp
