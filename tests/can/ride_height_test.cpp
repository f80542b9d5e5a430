// GVS_RideHeight and the scale source: what goes out as valid, and that the
// ECU can always tell which height the speed was scaled with.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "gvs/can/codec.hpp"

namespace gvs::can {
namespace {

BusEstimate measured_at(std::int64_t t_ns) {
  BusEstimate e;
  e.t_ns = t_ns;
  e.has_speed = e.has_direction = e.has_velocity_xy = true;
  e.speed_mps = 20.0;
  e.vx_mps = 20.0;
  e.quality = 0.9;
  e.scale_source = ScaleSourceCode::LaserDots;
  e.has_height = e.has_pitch = e.has_roll = true;
  e.height_mm = 58.73;
  e.pitch_deg = 1.21;
  e.roll_deg = -0.64;
  return e;
}

constexpr std::int64_t kT = 1'000'000'000;
const ValidityRule kRule{50, 0.3};

TEST(RideHeightFromEstimate, FreshMeasurementIsValidWithItsAge) {
  const BusEstimate e = measured_at(kT);
  const RideHeightMsg m = ride_height_from_estimate(&e, kT + 12'000'000, kRule);
  EXPECT_TRUE(m.height_valid);
  EXPECT_TRUE(m.pitch_valid && m.roll_valid);
  EXPECT_EQ(m.scale_source, ScaleSourceCode::LaserDots);
  EXPECT_DOUBLE_EQ(m.height_mm, 58.73);
  EXPECT_DOUBLE_EQ(m.pitch_deg, 1.21);
  EXPECT_EQ(m.age_ms, 12u);
  const MessageIds ids;
  const DecodedFrame d = decode(encode_ride_height(m, ids, 3), ids);
  ASSERT_EQ(d.status, DecodeStatus::Ok);
  ASSERT_EQ(d.kind, MessageKind::RideHeight);
  EXPECT_NEAR(d.ride.height_mm, 58.73, 0.005 + 1e-9);
  EXPECT_NEAR(d.ride.pitch_deg, 1.21, 0.005 + 1e-9);
  EXPECT_NEAR(d.ride.roll_deg, -0.64, 0.005 + 1e-9);
  EXPECT_EQ(d.ride.age_ms, 12u);
  EXPECT_EQ(d.ride.scale_source, ScaleSourceCode::LaserDots);
}

TEST(RideHeightFromEstimate, StaleMeasurementGoesOutInvalidAsZero) {
  const BusEstimate e = measured_at(kT);
  const RideHeightMsg m = ride_height_from_estimate(&e, kT + 51'000'000, kRule);
  EXPECT_FALSE(m.height_valid);
  EXPECT_FALSE(m.pitch_valid || m.roll_valid);
  EXPECT_EQ(m.age_ms, 51u);
  const MessageIds ids;
  const DecodedFrame d = decode(encode_ride_height(m, ids, 0), ids);
  EXPECT_EQ(d.ride.height_mm, 0.0);
  EXPECT_EQ(d.ride.pitch_deg, 0.0);
  EXPECT_EQ(d.ride.roll_deg, 0.0);
  // Even values set on an invalid message are not sent.
  RideHeightMsg sloppy;
  sloppy.height_mm = 61.0;
  sloppy.pitch_deg = 1.0;
  EXPECT_EQ(decode(encode_ride_height(sloppy, ids, 0), ids).ride.height_mm, 0.0);
  EXPECT_EQ(decode(encode_ride_height(sloppy, ids, 0), ids).ride.pitch_deg, 0.0);
}

TEST(RideHeightFromEstimate, NothingMeasuredIsInvalidWithAge127AndSaysNominal) {
  BusEstimate e = measured_at(kT);
  e.has_height = e.has_pitch = e.has_roll = false;
  e.scale_source = ScaleSourceCode::Nominal;
  const RideHeightMsg m = ride_height_from_estimate(&e, kT + 5'000'000, kRule);
  EXPECT_FALSE(m.height_valid || m.pitch_valid || m.roll_valid);
  EXPECT_EQ(m.age_ms, 127u);
  EXPECT_EQ(m.scale_source, ScaleSourceCode::Nominal);
  const RideHeightMsg none = ride_height_from_estimate(nullptr, kT, kRule);
  EXPECT_FALSE(none.height_valid || none.pitch_valid || none.roll_valid);
  EXPECT_EQ(none.age_ms, 127u);
}

TEST(RideHeightFromEstimate, AnAgePastSevenBitsSaturatesAt127) {
  // A stale limit set past 127 ms ([can] staleness_limit_ms reaches 1000):
  // the height is still valid, its age reads "127 ms or more".
  const BusEstimate e = measured_at(kT);
  const RideHeightMsg m = ride_height_from_estimate(&e, kT + 300'000'000, ValidityRule{500, 0.3});
  EXPECT_TRUE(m.height_valid);
  EXPECT_EQ(m.age_ms, 127u);
  const MessageIds ids;
  EXPECT_EQ(decode(encode_ride_height(m, ids, 0), ids).ride.age_ms, 127u);
}

TEST(RideHeightFromEstimate, TheRollGoesOutWithoutThePitch) {
  // Three dots without dot 0 or 1 fix the roll and not the pitch: each has
  // its own bit, and the one not measured goes out as 0.
  BusEstimate e = measured_at(kT);
  e.has_pitch = false;
  const RideHeightMsg m = ride_height_from_estimate(&e, kT + 2'000'000, kRule);
  EXPECT_TRUE(m.height_valid && m.roll_valid);
  EXPECT_FALSE(m.pitch_valid);
  const MessageIds ids;
  const DecodedFrame d = decode(encode_ride_height(m, ids, 5), ids);
  ASSERT_EQ(d.status, DecodeStatus::Ok);
  EXPECT_TRUE(d.ride.roll_valid);
  EXPECT_FALSE(d.ride.pitch_valid);
  EXPECT_EQ(d.ride.pitch_deg, 0.0);
  EXPECT_NEAR(d.ride.roll_deg, -0.64, 0.005 + 1e-9);
  EXPECT_EQ(d.ride.age_ms, 2u);
}

TEST(RideHeightFromEstimate, HeightWithoutTiltFromAnExternalSensor) {
  BusEstimate e = measured_at(kT);
  e.has_pitch = e.has_roll = false;
  e.scale_source = ScaleSourceCode::External;
  const RideHeightMsg m = ride_height_from_estimate(&e, kT + 3'000'000, kRule);
  EXPECT_TRUE(m.height_valid);
  EXPECT_FALSE(m.pitch_valid || m.roll_valid);
  EXPECT_EQ(m.pitch_deg, 0.0);
  EXPECT_EQ(m.scale_source, ScaleSourceCode::External);
}

TEST(RideHeightFromEstimate, OutOfRangeOrNonFiniteIsInvalidNotClamped) {
  BusEstimate e = measured_at(kT);
  e.height_mm = 700.0;  // above 655.35
  e.pitch_deg = 25.0;   // beyond +-20.47
  RideHeightMsg m = ride_height_from_estimate(&e, kT, kRule);
  EXPECT_FALSE(m.height_valid);
  EXPECT_FALSE(m.pitch_valid);
  EXPECT_TRUE(m.roll_valid) << "the roll in range goes out on its own";
  e.height_mm = std::numeric_limits<double>::quiet_NaN();
  e.pitch_deg = 0.0;
  e.roll_deg = std::numeric_limits<double>::infinity();
  m = ride_height_from_estimate(&e, kT, kRule);
  EXPECT_FALSE(m.height_valid);
  EXPECT_TRUE(m.pitch_valid);
  EXPECT_FALSE(m.roll_valid);
}

TEST(RideHeightFromEstimate, QualityAndPlausibilityOfTheVelocityDoNotGateTheHeight) {
  BusEstimate e = measured_at(kT);
  e.quality = 0.05;
  const RideHeightMsg m = ride_height_from_estimate(&e, kT + 1'000'000, kRule);
  EXPECT_TRUE(m.height_valid);
  EXPECT_FALSE(velocity_from_estimate(&e, kT + 1'000'000, kRule).velocity.valid);
}

TEST(VelocityXyScaleSource, SentWithEveryEstimateValidOrNot) {
  const MessageIds ids;
  BusEstimate e = measured_at(kT);
  e.scale_source = ScaleSourceCode::External;
  VelocityPair p = velocity_from_estimate(&e, kT + 1'000'000, kRule);
  EXPECT_EQ(decode(encode_velocity_xy(p.xy, ids, 0), ids).xy.scale_source, ScaleSourceCode::External);
  e.quality = 0.0;  // invalid: the scale source still says what the (unsent) value rested on
  p = velocity_from_estimate(&e, kT + 1'000'000, kRule);
  EXPECT_FALSE(p.xy.valid);
  EXPECT_EQ(decode(encode_velocity_xy(p.xy, ids, 0), ids).xy.scale_source, ScaleSourceCode::External);
  EXPECT_EQ(velocity_from_estimate(nullptr, kT, kRule).xy.scale_source, ScaleSourceCode::Nominal);
}

}  // namespace
}  // namespace gvs::can
