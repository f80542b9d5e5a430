// next_exposure(): the exposure / strobe plan follows the speed.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "gvs/dsp/exposure_control.hpp"

namespace gvs::dsp {
namespace {

VelocityEstimate moving(double speed_mps, Method method = Method::blur_cont) {
  VelocityEstimate e;
  e.has_speed = true;
  e.has_direction = true;
  e.speed_mps = speed_mps;
  e.vx_mps = speed_mps;
  e.quality = 0.9;
  e.method = method;
  return e;
}

double streak_px(double speed_mps, double t_us) { return speed_mps / 1e-4 * t_us * 1e-6; }

TEST(ExposureControl, FixedKeepsThePlan) {
  ExposurePlan current;
  current.exposure_us = 1234.0;
  const ExposurePlan next = next_exposure(moving(30.0), current, ExposureMode::fixed, {});
  EXPECT_EQ(next.exposure_us, 1234.0);
  EXPECT_EQ(next.pulse_count, 0u);
}

TEST(ExposureControl, AdaptiveAimsAtTheTargetStreakAndHoldsInsideTheBand) {
  const ExposureLimits lim;
  ExposurePlan current;  // 3000 us
  // 20 m/s with 3 ms: 600 px streak -> re-plan to 40 px.
  ExposurePlan next = next_exposure(moving(20.0), current, ExposureMode::adaptive, lim);
  // One LED strobe (a pulse, so the light may be overdriven) lasting the exposure.
  ASSERT_EQ(next.pulse_count, 1u);
  EXPECT_EQ(next.pulses[0].start_us, 0.0);
  EXPECT_EQ(next.pulses[0].duration_us, next.exposure_us);
  EXPECT_NEAR(streak_px(20.0, next.exposure_us), lim.target_streak_px, 0.5);
  // Speed up by 30 %: streak 65 px, still inside [40, 80]: no change (hysteresis).
  const ExposurePlan held = next_exposure(moving(26.0), next, ExposureMode::adaptive, lim);
  EXPECT_EQ(held.exposure_us, next.exposure_us);
  // Slow down by 15 %: 42.5 px, held; by 30 %: 35 px, re-planned (short
  // streaks read short: min_streak_px).
  EXPECT_EQ(next_exposure(moving(17.0), next, ExposureMode::adaptive, lim).exposure_us, next.exposure_us);
  const ExposurePlan slower = next_exposure(moving(14.0), next, ExposureMode::adaptive, lim);
  EXPECT_NEAR(streak_px(14.0, slower.exposure_us), lim.target_streak_px, 0.5);
  // Double the speed: 100 px, outside: re-plan.
  const ExposurePlan faster = next_exposure(moving(40.0), next, ExposureMode::adaptive, lim);
  EXPECT_NEAR(streak_px(40.0, faster.exposure_us), lim.target_streak_px, 0.5);
  // Slow: the exposure is capped at max_exposure_us.
  const ExposurePlan slow = next_exposure(moving(0.3), faster, ExposureMode::adaptive, lim);
  EXPECT_EQ(slow.exposure_us, lim.max_exposure_us);
  EXPECT_EQ(slow.pulse_count, 0u);  // the longest exposure is continuous light
}

VelocityEstimate direction_only(Method method, double quality = 0.9) {
  VelocityEstimate e;
  e.has_direction = true;
  e.quality = quality;
  e.method = method;
  return e;
}

ExposurePlan continuous_us(double t_us) {
  ExposurePlan p;
  p.exposure_us = t_us;
  return p;
}

TEST(ExposureControl, AdaptiveShortensWhenTheStreakIsTooLongToMeasure) {
  const ExposurePlan current;  // 3000 us
  const ExposurePlan next = next_exposure(direction_only(Method::streak_cont), current, ExposureMode::adaptive, {});
  EXPECT_DOUBLE_EQ(next.exposure_us, 1500.0);  // an octave: 3000 / 2
  // A short streak without speed at the longest exposure (a slow car: the
  // frame pairs measure it) does not shorten.
  EXPECT_EQ(next_exposure(direction_only(Method::blur_cont), current, ExposureMode::adaptive, {}).exposure_us, 3000.0);
}

// Dark single-strobe frames: below the texture SNR a streak length needs,
// a shorter strobe only loses light: the longest exposure (direction from
// long streaks); up to twice that SNR a too-long streak does not shorten.
// (Only frames that are not well lit: VelocityEstimate::pixel_snr.)
TEST(ExposureControl, AdaptiveInTheDarkTakesTheLongestExposure) {
  const ExposureLimits lim;
  VelocityEstimate dark = moving(20.0);  // 500 us: 100 px, but too dark for its length
  dark.texture_snr = 2.0;
  EXPECT_EQ(next_exposure(dark, continuous_us(500.0), ExposureMode::adaptive, lim).exposure_us,
            lim.max_exposure_us);
  VelocityEstimate dark_long = direction_only(Method::streak_cont);
  dark_long.texture_snr = 1.0;
  EXPECT_EQ(next_exposure(dark_long, continuous_us(3000.0), ExposureMode::adaptive, lim).exposure_us,
            lim.max_exposure_us);
  dark_long.texture_snr = 6.0;  // dim: held, not shortened
  EXPECT_EQ(next_exposure(dark_long, continuous_us(3000.0), ExposureMode::adaptive, lim).exposure_us,
            lim.max_exposure_us);
  dark_long.texture_snr = 30.0;  // bright: shortened an octave as in normal light
  EXPECT_DOUBLE_EQ(next_exposure(dark_long, continuous_us(3000.0), ExposureMode::adaptive, lim).exposure_us,
                   1500.0);
  // Not measured (0, e.g. a pair): the rule does not apply.
  VelocityEstimate fast = moving(20.0);
  EXPECT_LT(next_exposure(fast, continuous_us(3000.0), ExposureMode::adaptive, lim).exposure_us, 3000.0);
}

TEST(ExposureControl, AdaptiveLengthensWhenTheStreakIsTooShortForADirection) {
  const ExposureLimits lim;
  VelocityEstimate short_streak = no_estimate(0, 0, Method::short_streak);
  // With a recent speed (the car slowed faster than the plan followed): x4
  // per frame from the measured frame's light time, up to the longest exposure.
  short_streak.tracking = true;
  EXPECT_DOUBLE_EQ(next_exposure(short_streak, continuous_us(5.0), ExposureMode::adaptive, lim).exposure_us, 20.0);
  EXPECT_DOUBLE_EQ(next_exposure(short_streak, continuous_us(1000.0), ExposureMode::adaptive, lim).exposure_us,
                   lim.max_exposure_us);
  // Without one (the end of a sweep): the sweep starts again near the top,
  // a third of an octave below where the ended one began (5 us is
  // 3000 us / 2^9.23, nearest 2381 us / 2^9: the next starts at 1890 us).
  short_streak.tracking = false;
  EXPECT_NEAR(next_exposure(short_streak, continuous_us(5.0), ExposureMode::adaptive, lim).exposure_us,
              3000.0 / std::cbrt(4.0), 1e-6);
  EXPECT_NEAR(next_exposure(short_streak, continuous_us(3000.0 / 128.0), ExposureMode::adaptive, lim).exposure_us,
              3000.0 / std::cbrt(2.0), 1e-6);
  // Already at the longest exposure: a slow car (the frame pairs measure it).
  EXPECT_DOUBLE_EQ(next_exposure(short_streak, continuous_us(3000.0), ExposureMode::adaptive, lim).exposure_us,
                   3000.0);
}

TEST(ExposureControl, AdaptiveHoldsOnOneTooLongStreakWhileTrackingASpeed) {
  // A streak in the band (70 px at 31.8 m/s and 220 us) read as "too long"
  // on one frame while the last frames measured the speed: a miss, not a
  // change.
  VelocityEstimate miss = direction_only(Method::streak_cont);
  miss.tracking = true;
  EXPECT_DOUBLE_EQ(next_exposure(miss, continuous_us(220.0), ExposureMode::adaptive, {}).exposure_us, 220.0);
  miss.tracking = false;
  EXPECT_DOUBLE_EQ(next_exposure(miss, continuous_us(220.0), ExposureMode::adaptive, {}).exposure_us, 110.0);
}

// Frames that move but give no speed (e.g. "blur-*": a cold start's test
// for a streak end not met) must not hold any exposure for good: every
// octave is visited, then the sweep starts again from the longest exposure
// (docs/accuracy.md, "No lock-up without a speed").
TEST(ExposureControl, AdaptiveOnAWellLitFrameWithFaintStreakEndsIsNotDark) {
  // Faint ends on a well-lit frame are the ground's low contrast: the
  // strobe follows the speed instead of falling back to the longest exposure.
  const ExposureLimits lim;
  VelocityEstimate faint = moving(20.0);  // 500 us: 100 px
  faint.texture_snr = 2.0;
  faint.pixel_snr = VelocityEstimate::kWellLitPixelSnr + 5.0;
  EXPECT_NEAR(streak_px(20.0, next_exposure(faint, continuous_us(500.0), ExposureMode::adaptive, lim).exposure_us),
              lim.target_streak_px, 0.5);
  faint.pixel_snr = VelocityEstimate::kWellLitPixelSnr - 5.0;  // a dark frame
  EXPECT_EQ(next_exposure(faint, continuous_us(500.0), ExposureMode::adaptive, lim).exposure_us, lim.max_exposure_us);
}

TEST(ExposureControl, AdaptiveAimsAtALongerStreakOnADimFrame) {
  // Not well lit, but bright enough for a streak length: the longer strobe
  // brings more light (below the LED's rated pulse) and a longer axis.
  const ExposureLimits lim;
  VelocityEstimate dim = moving(40.0);  // 3000 us: far outside the band
  dim.texture_snr = 6.0;
  dim.pixel_snr = VelocityEstimate::kWellLitPixelSnr - 5.0;
  EXPECT_NEAR(streak_px(40.0, next_exposure(dim, continuous_us(3000.0), ExposureMode::adaptive, lim).exposure_us),
              lim.dark_target_streak_px, 0.5);
  dim.pixel_snr = VelocityEstimate::kWellLitPixelSnr + 5.0;
  EXPECT_NEAR(streak_px(40.0, next_exposure(dim, continuous_us(3000.0), ExposureMode::adaptive, lim).exposure_us),
              lim.target_streak_px, 0.5);
}

TEST(ExposureControl, AdaptiveLeavesTheLongestExposureWhenAWellLitStreakGivesNoSpeed) {
  const ExposureLimits lim;
  VelocityEstimate blurred = direction_only(Method::blur_cont);
  blurred.texture_snr = 2.0;
  blurred.pixel_snr = VelocityEstimate::kWellLitPixelSnr + 5.0;
  const ExposurePlan next = next_exposure(blurred, continuous_us(3000.0), ExposureMode::adaptive, lim);
  EXPECT_EQ(next.exposure_us, 1500.0);
  EXPECT_EQ(next.pulse_count, 1u);
  // Not while a recent speed is tracked (one miss), and not in the dark
  // (there the longest exposure keeps the direction).
  blurred.tracking = true;
  EXPECT_EQ(next_exposure(blurred, continuous_us(3000.0), ExposureMode::adaptive, lim).exposure_us, 3000.0);
  blurred.tracking = false;
  blurred.pixel_snr = VelocityEstimate::kWellLitPixelSnr - 5.0;
  EXPECT_EQ(next_exposure(blurred, continuous_us(3000.0), ExposureMode::adaptive, lim).exposure_us, 3000.0);
}

TEST(ExposureControl, AWellLitFrameWithoutTextureStepsDownLikeAStreakWithoutSpeed) {
  // Low-contrast ground, 2.4 ms from 80 km/h up: streaks of 540-930 px leave
  // no texture in the band, the frame is `no-texture` though well lit, and
  // without this rule the plan stayed there for good (no speed, no direction).
  const ExposureLimits lim;
  VelocityEstimate flat = no_estimate(0, 0, Method::no_texture);
  flat.pixel_snr = VelocityEstimate::kWellLitPixelSnr + 5.0;
  ExposurePlan strobe;
  strobe.pulse_count = 1;
  strobe.exposure_us = 2400.0;
  strobe.pulses[0] = {0.0, 2400.0};
  EXPECT_EQ(next_exposure(flat, strobe, ExposureMode::adaptive, lim).exposure_us, 1200.0);
  EXPECT_EQ(next_exposure(flat, continuous_us(3000.0), ExposureMode::adaptive, lim).exposure_us, 1500.0);
  // Double pulse: from the continuous exposure to the pulses (fast guess).
  EXPECT_EQ(next_exposure(flat, continuous_us(3000.0), ExposureMode::double_pulse, lim).pulse_count, 2u);
  // Held: while a recent speed is tracked (one miss), on a frame that is not
  // well lit (too little light to judge the texture by), and on a frame
  // without any contrast (frame_check: no pixel SNR measured).
  flat.tracking = true;
  EXPECT_EQ(next_exposure(flat, strobe, ExposureMode::adaptive, lim).exposure_us, 2400.0);
  EXPECT_EQ(next_exposure(flat, continuous_us(3000.0), ExposureMode::double_pulse, lim).pulse_count, 0u);
  flat.tracking = false;
  flat.pixel_snr = VelocityEstimate::kWellLitPixelSnr - 5.0;
  EXPECT_EQ(next_exposure(flat, strobe, ExposureMode::adaptive, lim).exposure_us, 2400.0);
  EXPECT_EQ(next_exposure(flat, continuous_us(3000.0), ExposureMode::double_pulse, lim).pulse_count, 0u);
  flat.pixel_snr = 0.0;
  EXPECT_EQ(next_exposure(flat, strobe, ExposureMode::adaptive, lim).exposure_us, 2400.0);
}

TEST(ExposureControl, AdaptiveWaitsForThePairOnADoubtfulFirstStreak) {
  // A run's first frame at 3 ms (`const` from 1 km/h on ph_asphalt_04: an
  // 8 px streak, no pair, the sign a guess) gives a direction at quality
  // 0.04. Swept down, the next frames have unequal exposures, whose pairs
  // do not match on that ground, and their short streaks restart the sweep:
  // no speed. Below min_quality the plan holds for the next frame's pair.
  const ExposureLimits lim;
  VelocityEstimate first = direction_only(Method::blur_fwd, 0.04);
  first.pixel_snr = VelocityEstimate::kWellLitPixelSnr + 5.0;
  EXPECT_EQ(next_exposure(first, continuous_us(3000.0), ExposureMode::adaptive, lim).exposure_us, 3000.0);
  first.quality = lim.min_quality;
  EXPECT_EQ(next_exposure(first, continuous_us(3000.0), ExposureMode::adaptive, lim).exposure_us, 1500.0);
  // A streak too long to measure sweeps down whatever its quality.
  EXPECT_EQ(next_exposure(direction_only(Method::streak_fwd, 0.01), continuous_us(3000.0), ExposureMode::adaptive, lim)
                .exposure_us,
            1500.0);
}

/// A cold start at 15 m/s, well lit, on ground whose streak gives a speed
/// only at lengths in [lo_px, hi_px]: too long above 100 px, no direction
/// below 10 px, a direction without speed between. Runs the adaptive loop
/// from the longest exposure; the frame index of the first speed (-1:
/// none in max_frames) and the plan that gave it.
struct ColdStart {
  int frames_to_speed = -1;
  ExposurePlan plan;
};
ColdStart cold_start(double lo_px, double hi_px, int max_frames) {
  const ExposureLimits lim;
  const double v_mps = 15.0;
  auto estimate_at = [&](double t_us) {
    const double streak = streak_px(v_mps, t_us);
    if (streak >= lo_px && streak <= hi_px) return moving(v_mps);
    VelocityEstimate e = streak > 100.0  ? direction_only(Method::streak_cont)
                         : streak < 10.0 ? no_estimate(0, 0, Method::short_streak)
                                         : direction_only(Method::blur_cont);
    e.pixel_snr = VelocityEstimate::kWellLitPixelSnr + 10.0;  // well lit
    return e;
  };
  ColdStart run;
  run.plan = continuous_us(lim.max_exposure_us);
  for (int i = 0; i < max_frames; ++i) {
    const VelocityEstimate e = estimate_at(run.plan.exposure_us);
    if (e.has_speed) {
      run.frames_to_speed = i;
      break;
    }
    run.plan = next_exposure(e, run.plan, ExposureMode::adaptive, lim);
  }
  return run;
}

TEST(ExposureControl, AdaptiveFindsTheOneMeasurableOctaveFromAColdStart) {
  // Measured only at 50-70 px (333-467 us): the sweep must reach the band,
  // not cycle over the octaves below it.
  EXPECT_EQ(cold_start(50.0, 70.0, 40).frames_to_speed, 3);  // 3000, 1500, 750 us, then 375 us: 56 px
}

TEST(ExposureControl, AdaptiveFindsANarrowMeasurableBandBetweenTheOctaves) {
  // Measured only at 40-48 px (267-320 us), between two octaves of 3000 us
  // (375 us: 56 px, 187.5 us: 28 px) (torcs_etrack2 `spin` adaptive: a cold
  // start measures a narrow band). A sweep restarted at the same exposure
  // would try 56 and 28 px forever; one restarted a third of an octave
  // lower reaches 297.6 us (44.6 px) in its second sweep.
  const ColdStart run = cold_start(40.0, 48.0, 60);
  // 3000 .. 46.9 us (frames 0-6; 7 px: too short for a direction), then
  // 2381, 1191, 595 and 298 us.
  EXPECT_EQ(run.frames_to_speed, 10);
  EXPECT_NEAR(run.plan.exposure_us, 3000.0 / std::cbrt(2.0) / 8.0, 1e-9);
}

TEST(ExposureControl, DoublePulseLeavesTheContinuousExposureWhenAWellLitStreakGivesNoSpeed) {
  // 3 ms at 11-87 km/h on low-contrast ground: a direction (blur-cont) but
  // no streak length. Without this rule the plan stayed at 3 ms for good.
  const ExposureLimits lim;
  VelocityEstimate blurred = direction_only(Method::blur_cont);
  blurred.pixel_snr = VelocityEstimate::kWellLitPixelSnr + 5.0;
  EXPECT_EQ(next_exposure(blurred, continuous_us(3000.0), ExposureMode::double_pulse, lim).pulse_count, 2u);
  blurred.tracking = true;  // one miss while a recent speed is tracked: hold
  EXPECT_EQ(next_exposure(blurred, continuous_us(3000.0), ExposureMode::double_pulse, lim).pulse_count, 0u);
  blurred.tracking = false;
  blurred.pixel_snr = VelocityEstimate::kWellLitPixelSnr - 5.0;  // dark: hold
  EXPECT_EQ(next_exposure(blurred, continuous_us(3000.0), ExposureMode::double_pulse, lim).pulse_count, 0u);
}

TEST(ExposureControl, AdaptiveSweepsTheOctavesWhenNoSpeedComes) {
  const ExposureLimits lim;
  ExposurePlan plan = continuous_us(750.0);
  std::vector<double> visited;
  for (int i = 0; i < 12; ++i) {
    // Even a low-quality direction (forward prior only) moves the sweep on.
    plan = next_exposure(direction_only(Method::blur_fwd, 0.1), plan, ExposureMode::adaptive, lim);
    visited.push_back(plan.exposure_us);
  }
  const std::vector<double> expected{375.0, 187.5, 93.75, 46.875, 23.4375, 11.71875, 5.859375,
                                     2.9296875, 3000.0 / std::cbrt(2.0)};
  ASSERT_EQ(visited.size(), 12u);
  for (std::size_t i = 0; i < expected.size(); ++i) EXPECT_NEAR(visited[i], expected[i], 1e-9) << "frame " << i;
  // The next sweep halves from 2381 us: it tries the lengths a third of an
  // octave below the first one's.
  EXPECT_NEAR(visited[9], 3000.0 / std::cbrt(2.0) / 2.0, 1e-9);
  // Its end starts a third sweep from 1890 us, and that one's from 3000 us
  // (continuous light), where a dim direction without a speed is a slow car:
  // held.
  for (int i = 0; i < 25; ++i) {
    plan = next_exposure(direction_only(Method::blur_fwd, 0.1), plan, ExposureMode::adaptive, lim);
    visited.push_back(plan.exposure_us);
  }
  const auto near = [&](double t_us) {
    return std::any_of(visited.begin(), visited.end(), [&](double v) { return std::abs(v - t_us) < 1e-6; });
  };
  EXPECT_TRUE(near(3000.0 / std::cbrt(4.0)));
  EXPECT_EQ(visited.back(), 3000.0);
  EXPECT_EQ(plan.pulse_count, 0u);
  // A frame with texture but no match at all (streak too short to show a
  // direction) continues the sweep too; a dark frame does not.
  EXPECT_EQ(next_exposure(no_estimate(0, 0, Method::no_match), continuous_us(100.0), ExposureMode::adaptive, lim)
                .exposure_us,
            50.0);
  EXPECT_EQ(next_exposure(no_estimate(0, 0, Method::dark), continuous_us(100.0), ExposureMode::adaptive, lim)
                .exposure_us,
            100.0);
  // A miss while the estimator still tracks a recent speed holds the plan
  // (the next frame is searched around that speed).
  VelocityEstimate warm_miss = direction_only(Method::blur_cont);
  warm_miss.tracking = true;
  EXPECT_EQ(next_exposure(warm_miss, continuous_us(300.0), ExposureMode::adaptive, lim).exposure_us, 300.0);
  // From the longest exposure, a too-long streak enters the sweep again.
  EXPECT_EQ(next_exposure(direction_only(Method::streak_cont), continuous_us(3000.0), ExposureMode::adaptive, lim)
                .exposure_us,
            1500.0);
}

// gvsd measures a frame while the next ones are already exposed under the
// current plan: steps start from the measured frame's light time, so such a
// frame repeats the plan already made instead of stepping twice.
TEST(ExposureControl, FramesInFlightDoNotStepTwice) {
  const ExposureLimits lim;
  const ExposurePlan frame = continuous_us(750.0);
  const ExposurePlan current = next_exposure(direction_only(Method::blur_cont), frame, frame, ExposureMode::adaptive, lim);
  ASSERT_EQ(current.exposure_us, 375.0);
  // The next frame, still taken at 750 us, repeats the 375 us plan.
  EXPECT_EQ(next_exposure(direction_only(Method::blur_cont), frame, current, ExposureMode::adaptive, lim).exposure_us,
            375.0);
  EXPECT_EQ(next_exposure(direction_only(Method::streak_cont), continuous_us(3000.0), continuous_us(1500.0),
                          ExposureMode::adaptive, lim)
                .exposure_us,
            1500.0);
  // At the bottom, a frame still at the shortest octave repeats the restart.
  const ExposurePlan restart = next_exposure(direction_only(Method::blur_cont), continuous_us(2.9296875),
                                             continuous_us(2.9296875), ExposureMode::adaptive, lim);
  EXPECT_EQ(next_exposure(direction_only(Method::blur_cont), continuous_us(2.9296875), restart,
                          ExposureMode::adaptive, lim)
                .exposure_us,
            restart.exposure_us);
}

TEST(ExposureControl, LowQualityAndNothingMeasuredKeepThePlan) {
  ExposurePlan current;
  current.exposure_us = 500.0;
  VelocityEstimate weak = moving(20.0);
  weak.quality = 0.1;
  EXPECT_EQ(next_exposure(weak, current, ExposureMode::adaptive, {}).exposure_us, 500.0);
  EXPECT_EQ(next_exposure(no_estimate(0, 0, Method::dark), current, ExposureMode::adaptive, {}).exposure_us, 500.0);
}

TEST(ExposureControl, DoublePulseSeparationGivesTheTargetDisplacement) {
  const ExposureLimits lim;
  ExposurePlan current;
  const ExposurePlan next = next_exposure(moving(40.0), current, ExposureMode::double_pulse, lim);
  ASSERT_EQ(next.pulse_count, 2u);
  const double c0 = next.pulses[0].start_us + next.pulses[0].duration_us / 2.0;
  const double c1 = next.pulses[1].start_us + next.pulses[1].duration_us / 2.0;
  EXPECT_NEAR(streak_px(40.0, c1 - c0), lim.target_shift_px, 0.5);
  EXPECT_LE(streak_px(40.0, next.pulses[0].duration_us), lim.max_pulse_blur_px + 1e-9);
  EXPECT_LE(next.exposure_us, lim.frame_period_us);
  // Held while the displacement stays in [min_shift, max_shift].
  const ExposurePlan held = next_exposure(moving(44.0), next, ExposureMode::double_pulse, lim);
  EXPECT_EQ(held.pulses[1].start_us, next.pulses[1].start_us);
  // Slow: back to one continuous exposure (pairs of frames work there).
  const ExposurePlan slow = next_exposure(moving(0.8), next, ExposureMode::double_pulse, lim);
  EXPECT_EQ(slow.pulse_count, 0u);
  EXPECT_EQ(slow.exposure_us, lim.max_exposure_us);
}

double separation_us(const ExposurePlan& p) {
  return (p.pulses[1].start_us + p.pulses[1].duration_us / 2.0) - (p.pulses[0].start_us + p.pulses[0].duration_us / 2.0);
}

// A dark double-pulse frame (texture SNR below min_pulse_texture_snr):
// longer pulses bring more light, up to dark_max_pulse_blur_px of streak
// each; a frame whose SNR has grown with that light holds the plan, and a
// bright frame brings back the short pulses.
TEST(ExposureControl, DarkDoublePulseFramesGetLongerPulses) {
  const ExposureLimits lim;
  const ExposurePlan bright = next_exposure(moving(40.0), ExposurePlan{}, ExposureMode::double_pulse, lim);
  ASSERT_EQ(bright.pulse_count, 2u);
  ASSERT_NEAR(streak_px(40.0, bright.pulses[0].duration_us), lim.max_pulse_blur_px, 1e-9);

  VelocityEstimate dark = moving(40.0, Method::dpiv_cont);
  dark.texture_snr = 2.5;  // 3 wanted: 2.4 px, within [0.5, 1.5] x 2 px: held
  EXPECT_EQ(next_exposure(dark, bright, bright, ExposureMode::double_pulse, lim).pulses[0].duration_us,
            bright.pulses[0].duration_us);
  dark.texture_snr = 1.2;  // 3 wanted: 5 px
  const ExposurePlan longer = next_exposure(dark, bright, bright, ExposureMode::double_pulse, lim);
  ASSERT_EQ(longer.pulse_count, 2u);
  EXPECT_NEAR(streak_px(40.0, longer.pulses[0].duration_us), 5.0, 1e-6);
  EXPECT_NEAR(streak_px(40.0, longer.pulses[1].duration_us), 5.0, 1e-6);
  EXPECT_NEAR(streak_px(40.0, separation_us(longer)), lim.target_shift_px, 0.5);

  dark.texture_snr = 0.5;  // would want 12 px: clamped
  const ExposurePlan darkest = next_exposure(dark, bright, bright, ExposureMode::double_pulse, lim);
  EXPECT_NEAR(streak_px(40.0, darkest.pulses[0].duration_us), lim.dark_max_pulse_blur_px, 1e-6);

  // The longer pulses gave 2.5x the light and SNR 3.1: held, not shortened again.
  dark.texture_snr = 3.1;
  const ExposurePlan held = next_exposure(dark, longer, longer, ExposureMode::double_pulse, lim);
  EXPECT_EQ(held.pulses[0].duration_us, longer.pulses[0].duration_us);
  // The light comes back (SNR 40 at 5 px): short pulses again.
  dark.texture_snr = 40.0;
  const ExposurePlan back = next_exposure(dark, longer, longer, ExposureMode::double_pulse, lim);
  EXPECT_NEAR(streak_px(40.0, back.pulses[0].duration_us), lim.max_pulse_blur_px, 1e-6);
}

// A 256x192 frame: the double image is found up to ~86 px (0.45 of 192), so
// the displacement aimed at is 50 px there, not 100.
TEST(ExposureControl, DoublePulseDisplacementFitsASmallFrame) {
  ExposureLimits lim;
  lim.frame_short_side_px = 192.0;
  const ExposurePlan next = next_exposure(moving(40.0), ExposurePlan{}, ExposureMode::double_pulse, lim);
  ASSERT_EQ(next.pulse_count, 2u);
  EXPECT_NEAR(streak_px(40.0, separation_us(next)), 50.0, 0.5);
  // Held inside the scaled band [25, 75] px: 60 px.
  EXPECT_EQ(next_exposure(moving(48.0), next, ExposureMode::double_pulse, lim).pulses[1].start_us,
            next.pulses[1].start_us);
  // At 384 px and above, the band is the configured one.
  lim.frame_short_side_px = 480.0;
  const ExposurePlan big = next_exposure(moving(40.0), ExposurePlan{}, ExposureMode::double_pulse, lim);
  EXPECT_NEAR(streak_px(40.0, separation_us(big)), lim.target_shift_px, 0.5);
}

// No speed from a double image: the separation shrinks 3x from the measured
// frame's, and when it cannot shrink further the plan restarts from the
// 30 m/s guess (no lock-up on a separation that never gives a speed).
TEST(ExposureControl, DoublePulseWithoutSpeedShrinksThenTriesTheLongExposure) {
  const ExposureLimits lim;
  const ExposurePlan guess = next_exposure(direction_only(Method::streak_cont), ExposurePlan{}, ExposureMode::double_pulse, lim);
  ASSERT_EQ(guess.pulse_count, 2u);
  EXPECT_NEAR(streak_px(30.0, separation_us(guess)), lim.target_shift_px, 0.5);
  ExposurePlan plan = guess;
  bool continuous = false;
  for (int i = 0; i < 10 && !continuous; ++i) {
    const ExposurePlan next = next_exposure(no_estimate(0, 0, Method::no_match), plan, ExposureMode::double_pulse, lim);
    if (next.pulse_count == 0) {
      // The separation cannot shrink any more: the car may be too slow for
      // any, and the pairs of the continuous exposure measure slow cars.
      continuous = true;
      EXPECT_EQ(next.exposure_us, lim.max_exposure_us);
    } else {
      ASSERT_EQ(next.pulse_count, 2u);
      EXPECT_NEAR(separation_us(next), separation_us(plan) / 3.0, 1e-6);
    }
    plan = next;
  }
  ASSERT_TRUE(continuous);
  // There, nothing measured holds the plan (the next frame's pair may), and
  // a clear streak without a speed starts again from the fast guess.
  EXPECT_EQ(next_exposure(no_estimate(0, 0, Method::no_match), plan, ExposureMode::double_pulse, lim).pulse_count, 0u);
  const ExposurePlan again = next_exposure(direction_only(Method::streak_cont), plan, ExposureMode::double_pulse, lim);
  ASSERT_EQ(again.pulse_count, 2u);
  EXPECT_EQ(separation_us(again), separation_us(guess));
}

TEST(ExposureControl, DoublePulseWaitsForThePairOnADoubtfulFirstStreak) {
  // A run's first frame at 3 ms (`const` from 1 km/h on ph_asphalt_04: an
  // 8 px streak, no pair, the sign a guess) gives a direction at quality
  // 0.04. Taken as too long it would send the plan to the 108 km/h guess,
  // and no separation measures 1 km/h; below min_quality the plan holds,
  // and the next frame's pair gives the speed.
  const ExposureLimits lim;
  VelocityEstimate first = direction_only(Method::blur_fwd, 0.04);
  first.pixel_snr = VelocityEstimate::kWellLitPixelSnr + 5.0;
  EXPECT_EQ(next_exposure(first, continuous_us(3000.0), ExposureMode::double_pulse, lim).pulse_count, 0u);
  first.quality = lim.min_quality;
  EXPECT_EQ(next_exposure(first, continuous_us(3000.0), ExposureMode::double_pulse, lim).pulse_count, 2u);
}

TEST(ExposureControl, UnequalSecondPulseEnergy) {
  ExposureLimits lim;
  lim.second_pulse_energy = 0.5;
  const ExposurePlan next = next_exposure(moving(40.0), ExposurePlan{}, ExposureMode::double_pulse, lim);
  ASSERT_EQ(next.pulse_count, 2u);
  EXPECT_NEAR(next.pulses[1].duration_us, 0.5 * next.pulses[0].duration_us, 1e-9);
}

TEST(ExposureControl, StandstillReturnsToTheLongExposure) {
  ExposurePlan current;
  current.exposure_us = 100.0;
  VelocityEstimate still = moving(0.0, Method::still);
  still.has_direction = false;
  EXPECT_EQ(next_exposure(still, current, ExposureMode::adaptive, {}).exposure_us, 3000.0);
}

TEST(ExposureControl, ParsesModeNames) {
  ExposureMode m = ExposureMode::fixed;
  EXPECT_TRUE(parse_exposure_mode("double-pulse", m));
  EXPECT_EQ(m, ExposureMode::double_pulse);
  EXPECT_TRUE(parse_exposure_mode("adaptive", m));
  EXPECT_EQ(m, ExposureMode::adaptive);
  EXPECT_FALSE(parse_exposure_mode("auto", m));
}

}  // namespace
}  // namespace gvs::dsp
