// The laser-dot finder against white grains taken for dots (docs/estimator.md,
// "Height from the laser dots", "Wrong dots"): a grain refused by the fourth
// dot; four that disagree keep the height only; the fourth found where three
// put it under a brighter grain; three dots without dot 0 or 1 keep the
// height only; a standing car's dots where they brightened since the last frame,
// four or three of them.
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
      if (d_dot <= kDotReachPx) v = background;                                              // the dot, gone
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
  EXPECT_FALSE(four.ride.has_pitch || four.ride.has_roll);

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
  ASSERT_TRUE(clean.ride.has_tilt());
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
    ASSERT_TRUE(trusted.ride.has_tilt());
    if (shift_px < 2.0) {
      EXPECT_TRUE(res.ride.has_tilt()) << "a dot 0.1 mm off hides at most 0.2 deg";
    } else {
      EXPECT_GT(std::abs(trusted.ride.pitch_deg - clean.ride.pitch_deg), 0.5) << "the tilt it would have sent";
      EXPECT_FALSE(res.ride.has_pitch || res.ride.has_roll)
          << "pitch " << trusted.ride.pitch_deg << " against " << clean.ride.pitch_deg;
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
  EXPECT_FALSE(finder.find(blotted(both, clean.dots[3])).ride.has_height);
}

TEST(LaserDots, ThreeDotsWithoutDotZeroOrOneKeepTheHeightAndRollNotThePitch) {
  // Dot 0 not seen (blotted out): the pitch then rests on dot 1 alone
  // against the x = 0 line of dots 2 and 3 (1.7 times the four dots'
  // scatter), nothing checks it, and the frame keeps its height and its
  // roll (dots 2 and 3, 40 mm apart). Without dot 2 the pitch rests on
  // dots 0 and 1 and both angles go out.
  LevelScene scene;
  auto& [c, f, finder, clean] = scene;
  ASSERT_EQ(clean.found, 4U);
  ASSERT_TRUE(clean.ride.has_tilt());
  const LaserDotResult no0 = finder.find(blotted(f.gray, clean.dots[0]));
  EXPECT_EQ(no0.found, 3U);
  ASSERT_TRUE(no0.ride.has_height);
  EXPECT_NEAR(no0.ride.height_mm, clean.ride.height_mm, 0.1);
  EXPECT_FALSE(no0.ride.has_pitch);
  ASSERT_TRUE(no0.ride.has_roll);
  EXPECT_NEAR(no0.ride.roll_deg, clean.ride.roll_deg, 0.2);
  const LaserDotResult no2 = finder.find(blotted(f.gray, clean.dots[2]));
  EXPECT_EQ(no2.found, 3U);
  ASSERT_TRUE(no2.ride.has_height);
  EXPECT_TRUE(no2.ride.has_tilt());
  EXPECT_NEAR(no2.ride.pitch_deg, clean.ride.pitch_deg, 0.2);
  EXPECT_NEAR(no2.ride.roll_deg, clean.ride.roll_deg, 0.2);
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
    ASSERT_TRUE(res.ride.has_height && res.ride.has_tilt());
    EXPECT_NEAR(res.dots[0].row, clean.dots[0].row, 0.5);
    EXPECT_NEAR(res.dots[0].col, clean.dots[0].col, 0.5);
    EXPECT_NEAR(res.ride.height_mm, clean.ride.height_mm, 0.05);
    EXPECT_NEAR(res.ride.pitch_deg, clean.ride.pitch_deg, 0.2);
    // The dot is masked where it is.
    EXPECT_NEAR(res.dots[0].mask_row, clean.dots[0].row, 0.5);
    EXPECT_NEAR(res.dots[0].mask_col, clean.dots[0].col, 0.5);
  }
}

TEST(LaserDots, AThreeDotPlaneWhoseFourthDotShowsBesideWhereItPutsItGivesNoHeight) {
  // Dot 3 on a dark stone (blotted out) with a spot as bright further along
  // its track, taken for it; dot 1 contested by a white grain 40 px along
  // its own track. No four agree, and the one plane of three with a single
  // choice each is dots 0 and 2 with the spot: tilted by the spot, it puts
  // dot 1 a few pixels from where dot 1 shows. A spot 6-12 px along (0.6-1.2
  // mm off its ground) makes that plane's height 0.3-0.6 mm off: no height
  // goes out. A spot 3-5 px along moves the plane so little that dot 1 is
  // found where it puts it, and the four agree within max_plane_residual_mm.
  LevelScene scene;
  auto& [c, f, finder, clean] = scene;
  ASSERT_EQ(clean.found, 4U);
  for (const double shift_px : {3.0, 5.0, 6.0, 9.0, 12.0}) {
    const cv::Mat spot3 = with_grain_for_dot(c, f.gray, clean.dots[3], 3, shift_px);
    const cv::Mat frame = with_grain_on_track(c, spot3, clean.dots[1], 1, 40.0, 1.0);
    const LaserDotResult res = finder.find(frame);
    if (shift_px < 5.5) {
      EXPECT_EQ(res.found, 4U) << shift_px << " px";
      ASSERT_TRUE(res.ride.has_height) << shift_px << " px";
      EXPECT_NEAR(res.ride.height_mm, clean.ride.height_mm, 0.15) << shift_px << " px";
    } else {
      EXPECT_EQ(res.dots[1].status, DotStatus::contested) << shift_px << " px: the scene must leave dot 1 contested";
      EXPECT_FALSE(res.ride.has_height) << shift_px << " px: height " << res.ride.height_mm << " against "
                                        << clean.ride.height_mm;
    }
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
  const StandingPair s(double_pulse(), 0.6);
  const auto& [c, plan, f0, f1, clean0, clean1, grains] = s;
  ASSERT_EQ(clean0.found, 4U);
  ASSERT_EQ(clean1.found, 4U);
  ASSERT_NEAR(clean1.ride.height_mm - clean0.ride.height_mm, 0.6, 0.05);
  const double background = clean0.dots[3].mask_background_dn;
  const cv::Mat frame0 = with_grains(f0.gray, grains, {&clean0.dots[3]}, 0.5, background);
  const cv::Mat frame1 = with_grains(f1.gray, grains, {&clean1.dots[1], &clean1.dots[3]}, 0.5, background);
  LaserDotFinder alone(c.camera, kNominalMm, c.lasers);
  ASSERT_FALSE(alone.find(frame1).ride.has_height);

  LaserDotFinder finder(c.camera, kNominalMm, c.lasers);
  const auto t_mid = [&s](const drivers::SimFrame& f) { return s.t_mid(f); };
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

TEST(LaserDots, AStandingCarsThreeDotsThatBrightenedGiveThePlaneWhereTheFourthLiesOnADarkStone) {
  // The scene above, and in the second frame dot 2 lands on a stone too dark
  // to show it: three dots brightened, moved together by the heave, and
  // their plane puts the fourth where the heave put it: the height, not the
  // tilt (the dots' scatter on sharp ground). A spot that appears
  // on the fourth track 8 px beside that point is the fourth dot elsewhere
  // (one of the three is not a dot): no height.
  const StandingPair s(double_pulse(), 0.6);
  const auto& [c, plan, f0, f1, clean0, clean1, grains] = s;
  ASSERT_EQ(clean0.found, 4U);
  ASSERT_EQ(clean1.found, 4U);
  const double background = clean0.dots[3].mask_background_dn;
  const cv::Mat frame0 = with_grains(f0.gray, grains, {&clean0.dots[3]}, 0.5, background);
  const cv::Mat frame1 =
      blotted(with_grains(f1.gray, grains, {&clean1.dots[1], &clean1.dots[3]}, 0.5, background), clean1.dots[2]);
  LaserDotFinder alone(c.camera, kNominalMm, c.lasers);
  ASSERT_FALSE(alone.find(frame1).ride.has_height);
  const auto t_mid = [&s](const drivers::SimFrame& f) { return s.t_mid(f); };

  LaserDotFinder finder(c.camera, kNominalMm, c.lasers);
  ASSERT_TRUE(finder.find(frame0, t_mid(f0), plan.exposure_us).ride.has_height);
  const LaserDotResult res = finder.find(frame1, t_mid(f1), plan.exposure_us);
  ASSERT_TRUE(res.ride.has_height);
  EXPECT_EQ(res.found, 3U);
  EXPECT_FALSE(res.dots[2].found);
  EXPECT_NEAR(res.ride.height_mm, clean1.ride.height_mm, 0.05);
  // A standing car's three dots on sharp ground vouch for the height only.
  EXPECT_FALSE(res.ride.has_pitch);
  EXPECT_FALSE(res.ride.has_roll);

  std::array<double, 2> beside{};
  along_track(c, clean1.dots[2], 2, 8.0, beside[0], beside[1]);
  const cv::Mat frame1_beside = with_grains(frame1, {beside}, {}, 1.0, clean1.dots[2].mask_background_dn);
  LaserDotFinder doubting(c.camera, kNominalMm, c.lasers);
  ASSERT_TRUE(doubting.find(frame0, t_mid(f0), plan.exposure_us).ride.has_height);
  EXPECT_FALSE(doubting.find(frame1_beside, t_mid(f1), plan.exposure_us).ride.has_height);
}

TEST(LaserDots, AStandingCarsFaintDotsShowAgainstTheLastPlanesFrameScaledByTheHeave) {
  // HeavedStandingPair: the grains' edges left in the difference of the two
  // frames as they are bury the two dimmed dots; against the first frame
  // scaled by the height change all four stand out: the right height, and
  // no tilt (faint dots on dark stones).
  const HeavedStandingPair s;
  ASSERT_EQ(s.clean0.found, 4U);
  ASSERT_EQ(s.clean1.found, 4U);
  ASSERT_NEAR(s.clean1.ride.height_mm - s.clean0.ride.height_mm, 1.0, 0.05);
  LaserDotFinder alone(s.c.camera, kNominalMm, s.c.lasers);
  ASSERT_FALSE(alone.find(s.frame1).ride.has_height);

  LaserDotFinder finder(s.c.camera, kNominalMm, s.c.lasers);
  const LaserDotResult first = finder.find(s.frame0, s.t_mid(s.f0), s.plan.exposure_us);
  ASSERT_TRUE(first.ride.has_height && first.ride.has_tilt());
  const LaserDotResult res = finder.find(s.frame1, s.t_mid(s.f1), s.plan.exposure_us);
  ASSERT_TRUE(res.ride.has_height);
  EXPECT_EQ(res.found, 4U);
  EXPECT_NEAR(res.ride.height_mm, s.clean1.ride.height_mm, 0.05);
  EXPECT_FALSE(res.ride.has_pitch);
  EXPECT_FALSE(res.ride.has_roll);
  for (const std::size_t k : {std::size_t{0}, std::size_t{2}}) {
    EXPECT_NEAR(res.dots[k].row, s.clean1.dots[k].row, 1.0) << "dot " << k;
    EXPECT_NEAR(res.dots[k].col, s.clean1.dots[k].col, 1.0) << "dot " << k;
  }
}

TEST(LaserDots, FourGrainsOnAPlaneTiltedPastTheLimitDiagonallyAreNotTheGround) {
  // A standing car 1.5 mm above the nominal height, white grains on tracks 1
  // and 3 brighter than their dots, dots 0 and 2 on dark stones (0.4 of
  // their contrast): the two grains and two of the ground's own grains on
  // tracks 0 and 2 agree on one plane within 0.1 mm, 3.2 mm too high,
  // pitched by 2.8 deg and rolled by 2.5 (each within max_tilt_deg, together
  // 3.7 deg). The ground does not tilt that far in any direction: no height
  // rather than that one.
  core::ExposurePlan plan;
  plan.exposure_us = 3000.0;
  const StandingPair s(plan, 1.5);
  const cv::Mat frame = with_grains(s.f1.gray, s.grains, {&s.clean1.dots[0], &s.clean1.dots[2]}, 0.4,
                                    s.clean1.dots[0].mask_background_dn);
  LaserDotFinder finder(s.c.camera, kNominalMm, s.c.lasers);
  const LaserDotResult res = finder.find(frame);
  if (res.ride.has_height) {
    EXPECT_NEAR(res.ride.height_mm, s.clean1.ride.height_mm, 0.15);
  }
  for (const std::size_t k : {std::size_t{1}, std::size_t{3}}) {
    const bool on_grain = res.dots[k].found && std::hypot(res.dots[k].row - s.grains[k == 1 ? 0 : 1][0],
                                                          res.dots[k].col - s.grains[k == 1 ? 0 : 1][1]) < 3.0;
    EXPECT_FALSE(on_grain && res.ride.has_height) << "dot " << k << " taken on the grain, and a height given";
  }
}

}  // namespace
}  // namespace gvs::dsp::laser_test
