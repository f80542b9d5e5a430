// The plausibility gate alone, with injected outliers: what a car cannot do
// is held back, what it can do passes, and the gate finds the car again
// after a gap or after it latched on an outlier.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>

#include "gvs/daemon/plausibility_gate.hpp"

namespace gvs::daemon {
namespace {

constexpr std::int64_t kFrameNs = 16'666'667;  // 60 fps
constexpr double kKmh = 1.0 / 3.6;

core::VelocityEstimate moving(std::int64_t t_ns, double speed_mps, double direction_deg = 0.0) {
  core::VelocityEstimate e;
  e.t_ns = t_ns;
  e.has_speed = true;
  e.has_direction = speed_mps >= core::VelocityEstimate::kStandstillMps;
  e.speed_mps = speed_mps;
  e.direction_deg = e.has_direction ? direction_deg : 0.0;
  e.vx_mps = speed_mps * std::cos(direction_deg * M_PI / 180.0);
  e.vy_mps = speed_mps * std::sin(direction_deg * M_PI / 180.0);
  e.quality = 0.9;
  e.method = core::Method::pair;
  return e;
}

/// `frames` estimates at a constant speed from t = 0; returns the next frame time.
std::int64_t cruise(PlausibilityGate& gate, double speed_mps, int frames, std::int64_t t0_ns = 0) {
  std::int64_t t = t0_ns;
  for (int i = 0; i < frames; ++i, t += kFrameNs) {
    const Plausibility p = gate.check(moving(t, speed_mps));
    EXPECT_TRUE(publishable(p)) << "cruise frame " << i << ": " << to_string(p);
  }
  return t;
}

TEST(PlausibilityGate, SixtyKmhToStandstillInOneFrameIsRejected) {
  PlausibilityGate gate;
  std::int64_t t = cruise(gate, 60 * kKmh, 30);
  EXPECT_EQ(gate.check(moving(t, 0.0)), Plausibility::rejected) << "60 km/h -> 0 in 17 ms is 100 g";
  t += kFrameNs;
  EXPECT_NEAR(gate.track().speed_mps, 60 * kKmh, 1e-9) << "an outlier does not move the track";
  EXPECT_EQ(gate.check(moving(t, 60 * kKmh)), Plausibility::accepted) << "the car is still at 60 km/h";
}

TEST(PlausibilityGate, RealisticBrakingAtOneAndAHalfGPassesToStandstill) {
  PlausibilityGate gate;
  const double decel_mps2 = 1.5 * 9.81;
  double v = 25.0;
  std::int64_t t = 0;
  int frame = 0;
  while (v > 0.0) {
    const double noise = (frame % 2 == 0 ? 1.0 : -1.0) * std::min(0.15, 0.01 * v + 0.05);  // measurement noise
    const Plausibility p = gate.check(moving(t, std::max(0.0, v + noise)));
    EXPECT_TRUE(publishable(p)) << "at " << v << " m/s: " << to_string(p);
    v -= decel_mps2 * 1e-9 * static_cast<double>(kFrameNs);
    t += kFrameNs;
    ++frame;
  }
  EXPECT_EQ(gate.check(moving(t, 0.0)), Plausibility::accepted) << "the car stands";
  EXPECT_GT(frame, 100);
}

TEST(PlausibilityGate, TheBoundIsAccelerationTimesIntervalPlusTheNoiseAllowance) {
  const PlausibilityLimits l;
  // 20 m/s: allowance max(0.3, 5 % of 20) = 1 m/s, plus 29.4 m/s^2 * 50 ms.
  const double bound = l.max_accel_mps2 * 0.050 + 1.0;
  PlausibilityGate gate;
  ASSERT_EQ(gate.check(moving(0, 20.0)), Plausibility::started);
  EXPECT_EQ(gate.check(moving(50'000'000, 20.0 + bound + 0.01)), Plausibility::rejected);
  EXPECT_EQ(gate.check(moving(50'000'000, 20.0 - bound - 0.01)), Plausibility::rejected);
  EXPECT_EQ(gate.check(moving(50'000'000, 20.0 + bound - 0.01)), Plausibility::accepted);
  // At low speed the absolute allowance (0.3 m/s) counts, not 5 %.
  PlausibilityGate slow;
  ASSERT_EQ(slow.check(moving(0, 1.0)), Plausibility::started);
  EXPECT_EQ(slow.check(moving(kFrameNs, 1.0 + 0.3 + 0.49 - 0.02)), Plausibility::accepted);
  PlausibilityGate slow2;
  ASSERT_EQ(slow2.check(moving(0, 1.0)), Plausibility::started);
  EXPECT_EQ(slow2.check(moving(kFrameNs, 1.0 + 0.3 + 0.49 + 0.02)), Plausibility::rejected);
  // A tighter limit (reload) applies to the next estimate.
  PlausibilityLimits tight;
  tight.max_accel_mps2 = 5.0;
  gate.set_limits(tight);
  // Track 20 + bound - 0.01 m/s; a 1.4 m/s step one frame later is within the
  // default bound (0.49 + 1.07 m/s) but not within 5 m/s^2 (0.08 + 1.07 m/s).
  EXPECT_EQ(gate.check(moving(50'000'000 + kFrameNs, 20.0 + bound - 0.01 + 1.4)), Plausibility::rejected);
}

TEST(PlausibilityGate, ReacquiresAfterAGap) {
  PlausibilityGate gate;
  std::int64_t t = cruise(gate, 30.0, 10);
  // No estimate for 0.6 s (camera gap), then the car crawls: the track has
  // timed out and the new estimate starts a new one.
  t += 600'000'000;
  EXPECT_EQ(gate.check(moving(t, 2.0)), Plausibility::started);
  EXPECT_NEAR(gate.track().speed_mps, 2.0, 1e-9);
  EXPECT_EQ(gate.check(moving(t + kFrameNs, 2.1)), Plausibility::accepted);
}

TEST(PlausibilityGate, ReacquiresWhenItLatchedOnAnOutlier) {
  PlausibilityGate gate;
  // The first estimate after start was wrong (30 m/s); the car drives at 10 m/s.
  ASSERT_EQ(gate.check(moving(0, 30.0)), Plausibility::started);
  std::int64_t t = kFrameNs;
  const int n = gate.limits().reacquire_count;
  for (int i = 1; i < n; ++i, t += kFrameNs) {
    EXPECT_EQ(gate.check(moving(t, 10.0 + 0.05 * i)), Plausibility::rejected) << i;
  }
  EXPECT_EQ(gate.check(moving(t, 10.2)), Plausibility::reacquired) << "the " << n << "th that agree";
  EXPECT_NEAR(gate.track().speed_mps, 10.2, 1e-9);
  EXPECT_EQ(gate.check(moving(t + kFrameNs, 10.2)), Plausibility::accepted);
}

TEST(PlausibilityGate, OutliersThatDisagreeWithEachOtherNeverReacquire) {
  PlausibilityGate gate;
  std::int64_t t = cruise(gate, 20.0, 10);
  for (int i = 0; i < 20; ++i, t += kFrameNs) {
    // Alternating wild values, each also far from the one before.
    const double wild = i % 2 == 0 ? 0.0 : 45.0;
    EXPECT_EQ(gate.check(moving(t, wild)), Plausibility::rejected) << i;
    if (i == 9) {  // the real car in between keeps the track alive
      EXPECT_EQ(gate.check(moving(t, 20.0)), Plausibility::accepted);
    }
  }
}

TEST(PlausibilityGate, DirectionFlipAtSpeedIsRejectedASpinIsNot) {
  PlausibilityGate gate;
  std::int64_t t = 0;
  for (int i = 0; i < 10; ++i, t += kFrameNs) ASSERT_TRUE(publishable(gate.check(moving(t, 15.0, 2.0))));
  // 180 deg in one frame at 15 m/s (a streak read backwards).
  EXPECT_EQ(gate.check(moving(t, 15.0, -178.0)), Plausibility::rejected);
  // A spin: the vehicle axes turn at 200 deg/s while the velocity keeps its
  // world direction, so the direction sweeps 3.3 deg per frame.
  double dir = 2.0;
  for (int i = 0; i < 30; ++i) {
    t += kFrameNs;
    dir -= 200.0 * 1e-9 * static_cast<double>(kFrameNs);
    EXPECT_EQ(gate.check(moving(t, 15.0, dir)), Plausibility::accepted) << dir;
  }
  // A direction-only estimate is checked against the tracked direction too.
  core::VelocityEstimate flipped = moving(t + kFrameNs, 15.0, dir + 180.0);
  flipped.has_speed = false;
  EXPECT_EQ(gate.check(flipped), Plausibility::rejected);
}

TEST(PlausibilityGate, DirectionIsFreeNearStandstill) {
  PlausibilityGate gate;
  ASSERT_EQ(gate.check(moving(0, 0.5, 0.0)), Plausibility::started);
  EXPECT_EQ(gate.check(moving(kFrameNs, 0.5, 120.0)), Plausibility::accepted) << "0.5 m/s: a car may turn at will";
  // From standstill the car may leave in any direction.
  EXPECT_EQ(gate.check(moving(2 * kFrameNs, 0.0)), Plausibility::accepted);
  EXPECT_FALSE(gate.track().has_direction);
  EXPECT_EQ(gate.check(moving(3 * kFrameNs, 0.4, -90.0)), Plausibility::accepted);
}

TEST(PlausibilityGate, EstimatesWithoutSpeedOrDirectionAreNotJudged) {
  PlausibilityGate gate;
  const std::int64_t t = cruise(gate, 20.0, 5);
  const core::VelocityEstimate none = core::no_estimate(7, t, core::Method::dark);
  EXPECT_EQ(gate.check(none), Plausibility::unchecked);
  EXPECT_NEAR(gate.track().speed_mps, 20.0, 1e-9);
  core::VelocityEstimate nan_speed = moving(t, 20.0);
  nan_speed.speed_mps = std::nan("");
  nan_speed.has_direction = false;
  EXPECT_EQ(gate.check(nan_speed), Plausibility::unchecked) << "a NaN is no speed (the codec flags it invalid)";
  gate.reset();
  EXPECT_FALSE(gate.tracking());
  EXPECT_EQ(gate.check(moving(t, 3.0)), Plausibility::started);
}

}  // namespace
}  // namespace gvs::daemon
