// next_exposure(): the exposure / strobe plan follows the speed.
#include <gtest/gtest.h>

#include "gvs/dsp/exposure_control.hpp"

namespace gvs::dsp {
namespace {

VelocityEstimate moving(double speed_mps, const char* method = "blur-cont") {
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
  EXPECT_EQ(next.pulse_count, 0u);
  EXPECT_NEAR(streak_px(20.0, next.exposure_us), lim.target_streak_px, 0.5);
  // Speed up by 30 %: streak 65 px, still inside [25, 80]: no change (hysteresis).
  const ExposurePlan held = next_exposure(moving(26.0), next, ExposureMode::adaptive, lim);
  EXPECT_EQ(held.exposure_us, next.exposure_us);
  // Double the speed: 100 px, outside: re-plan.
  const ExposurePlan faster = next_exposure(moving(40.0), next, ExposureMode::adaptive, lim);
  EXPECT_NEAR(streak_px(40.0, faster.exposure_us), lim.target_streak_px, 0.5);
  // Slow: the exposure is capped at max_exposure_us.
  const ExposurePlan slow = next_exposure(moving(0.3), faster, ExposureMode::adaptive, lim);
  EXPECT_EQ(slow.exposure_us, lim.max_exposure_us);
}

TEST(ExposureControl, AdaptiveShortensWhenTheStreakIsTooLongToMeasure) {
  VelocityEstimate e;
  e.has_direction = true;
  e.quality = 0.9;
  e.method = "streak-cont";
  ExposurePlan current;
  const ExposurePlan next = next_exposure(e, current, ExposureMode::adaptive, {});
  EXPECT_DOUBLE_EQ(next.exposure_us, 750.0);  // 3000 / 4
  // A short streak without speed (too slow for a length) does not shorten.
  e.method = "blur-cont";
  EXPECT_EQ(next_exposure(e, current, ExposureMode::adaptive, {}).exposure_us, 3000.0);
}

TEST(ExposureControl, LowQualityAndNothingMeasuredKeepThePlan) {
  ExposurePlan current;
  current.exposure_us = 500.0;
  VelocityEstimate weak = moving(20.0);
  weak.quality = 0.1;
  EXPECT_EQ(next_exposure(weak, current, ExposureMode::adaptive, {}).exposure_us, 500.0);
  EXPECT_EQ(next_exposure(no_estimate(0, 0, "dark"), current, ExposureMode::adaptive, {}).exposure_us, 500.0);
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
  VelocityEstimate still = moving(0.0, "still");
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
