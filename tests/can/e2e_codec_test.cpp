#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include "gvs/can/codec.hpp"
#include "gvs/can/e2e.hpp"

namespace gvs::can {
namespace {

std::uint8_t crc_of(std::vector<std::uint8_t> bytes) { return crc8_autosar(bytes.data(), bytes.size()); }

TEST(Crc8Autosar, CheckValueAndAutosarTestVectors) {
  EXPECT_EQ(crc_of({'1', '2', '3', '4', '5', '6', '7', '8', '9'}), 0xDF);
  // AUTOSAR SWS CRC Library, CRC8H2F examples.
  EXPECT_EQ(crc_of({0x00, 0x00, 0x00, 0x00}), 0x12);
  EXPECT_EQ(crc_of({0xF2, 0x01, 0x83}), 0xC2);
  EXPECT_EQ(crc_of({0x0F, 0xAA, 0x00, 0x55}), 0xC6);
  EXPECT_EQ(crc_of({0x00, 0xFF, 0x55, 0x11}), 0x77);
  EXPECT_EQ(crc_of({0x33, 0x22, 0x55, 0xAA, 0xBB, 0xCC, 0xDD, 0xEE, 0xFF}), 0x11);
  EXPECT_EQ(crc_of({0x92, 0x6B, 0x55}), 0x33);
  EXPECT_EQ(crc_of({0xFF, 0xFF, 0xFF, 0xFF}), 0x6C);
}

TEST(Crc8Autosar, ContinuesOverBlocks) {
  const std::uint8_t all[] = {1, 2, 3, 4, 5, 6, 7, 8};
  const std::uint8_t first = crc8_autosar(all, 3);
  EXPECT_EQ(crc8_autosar(all + 3, 5, first), crc8_autosar(all, 8));
}

TEST(E2e, ProtectedFrameChecksAndAnySingleBitFlipIsCaught) {
  CanFrame f;
  f.id = 0x301;
  f.len = 8;
  f.data = {0, 0xA0, 1, 2, 3, 4, 5, 6};
  e2e_protect(f, 7);
  EXPECT_EQ(e2e_counter(f), 7);
  EXPECT_EQ(f.data[1] & 0xF0, 0xA0) << "counter must keep the high nibble";
  // CRC over bytes 1..7 then the data ID (low byte of the CAN ID).
  const std::vector<std::uint8_t> input = {f.data[1], f.data[2], f.data[3], f.data[4], f.data[5], f.data[6], f.data[7], 0x01};
  EXPECT_EQ(f.data[0], crc_of(input));
  EXPECT_TRUE(e2e_crc_ok(f));
  for (std::size_t byte = 0; byte < 8; ++byte) {
    for (int bit = 0; bit < 8; ++bit) {
      CanFrame g = f;
      g.data[byte] = static_cast<std::uint8_t>(g.data[byte] ^ (1u << bit));
      EXPECT_FALSE(e2e_crc_ok(g)) << byte << ":" << bit;
    }
  }
  CanFrame other_id = f;
  other_id.id = 0x302;
  EXPECT_FALSE(e2e_crc_ok(other_id)) << "the data ID is part of the CRC";
  CanFrame short_frame = f;
  short_frame.len = 7;
  EXPECT_FALSE(e2e_crc_ok(short_frame));
}

TEST(E2e, CounterDeltaWraps) {
  EXPECT_EQ(e2e_counter_delta(15, 0), 1);
  EXPECT_EQ(e2e_counter_delta(3, 4), 1);
  EXPECT_EQ(e2e_counter_delta(3, 3), 0);
  EXPECT_EQ(e2e_counter_delta(14, 2), 4);
}

TEST(Encoder, CounterStepsPerMessageIdAndWraps) {
  Encoder enc({});
  for (int i = 0; i < 40; ++i) {
    const CanFrame v = enc.velocity({});
    const CanFrame x = enc.velocity_xy({});
    EXPECT_EQ(e2e_counter(v), i % 16);
    EXPECT_EQ(e2e_counter(x), i % 16);
    EXPECT_TRUE(e2e_crc_ok(v));
    EXPECT_TRUE(e2e_crc_ok(x));
    if (i % 5 == 0) {
      const CanFrame s = enc.status({});
      EXPECT_EQ(e2e_counter(s), (i / 5) % 16);
    }
  }
}

TEST(Encoder, RejectsBadConfigWithAMessage) {
  EXPECT_THROW(Encoder({0x7FD}), std::invalid_argument);
  try {
    Encoder bad({0x800});
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("0x800"), std::string::npos) << e.what();
  }
  EXPECT_NO_THROW(Encoder({0x7FB}));
}

TEST(Encoder, ConfigurableBaseIdMovesAllIdsAndDataIds) {
  Encoder enc({0x123});
  const CanFrame v = enc.velocity({});
  const CanFrame x = enc.velocity_xy({});
  const CanFrame s = enc.status({});
  const CanFrame t = enc.timing({});
  EXPECT_EQ(v.id, 0x123u);
  EXPECT_EQ(x.id, 0x124u);
  EXPECT_EQ(s.id, 0x125u);
  EXPECT_EQ(t.id, 0x126u);
  for (const CanFrame& f : {v, x, s, t}) {
    EXPECT_TRUE(e2e_crc_ok(f));
    EXPECT_EQ(decode(f, MessageIds{0x123}).status, DecodeStatus::Ok);
    EXPECT_EQ(decode(f, MessageIds{0x300}).status, DecodeStatus::NotOurs);
  }
}

TEST(Codec, RoundTripWithinHalfAStep) {
  const MessageIds ids;
  for (double speed = 0.0; speed <= 81.91; speed += 0.637) {
    for (double dir = -180.0; dir <= 180.0; dir += 13.37) {
      const VelocityMsg in{true, true, true, true, speed, dir, dir * 1.1, 50.0};
      const DecodedFrame d = decode(encode_velocity(in, ids, 0), ids);
      ASSERT_EQ(d.status, DecodeStatus::Ok);
      EXPECT_NEAR(d.velocity.speed_mps, speed, 0.005 + 1e-9);
      EXPECT_NEAR(d.velocity.direction_deg, dir, 0.005 + 1e-9);
      EXPECT_NEAR(d.velocity.yaw_rate_dps, dir * 1.1, 0.05 + 1e-9);
      EXPECT_TRUE(d.velocity.valid && d.velocity.speed_valid && d.velocity.direction_valid &&
                  d.velocity.yaw_rate_valid);
    }
  }
  // 250 km/h in x and y.
  const double v250 = 250.0 / 3.6;
  const DecodedFrame d = decode(encode_velocity_xy({true, v250, -v250, 12}, ids, 0), ids);
  EXPECT_NEAR(d.xy.vx_mps, v250, 0.0025 + 1e-9);
  EXPECT_NEAR(d.xy.vy_mps, -v250, 0.0025 + 1e-9);
  EXPECT_EQ(d.xy.age_ms, 12u);
}

TEST(Codec, StatusAndTimingRoundTrip) {
  const MessageIds ids;
  const StatusMsg s{SensorState::Fault, 0x0555, 200, 3, 77, 42};
  const DecodedFrame d = decode(encode_status(s, ids, 1), ids);
  EXPECT_EQ(d.status_msg.state, SensorState::Fault);
  EXPECT_EQ(d.status_msg.faults, 0x0555);
  EXPECT_EQ(d.status_msg.dropped_frames, 200);
  EXPECT_EQ(d.status_msg.ring_overruns, 3);
  EXPECT_EQ(d.status_msg.can_send_errors, 77);
  EXPECT_EQ(d.status_msg.method, 42);
  const DecodedFrame t = decode(encode_timing({70000, 1234, 5}, ids, 1), ids);
  EXPECT_EQ(t.timing.exposure_us, 65535u) << "saturates";
  EXPECT_EQ(t.timing.processing_time_us, 1234u);
  EXPECT_EQ(t.timing.late_wakeups, 5);
}

BusEstimate estimate_at(std::int64_t t_ns) {
  BusEstimate e;
  e.t_ns = t_ns;
  e.has_speed = e.has_direction = e.has_yaw_rate = e.has_velocity_xy = true;
  e.vx_mps = 10.0;
  e.vy_mps = 1.0;
  e.speed_mps = std::hypot(10.0, 1.0);
  e.direction_deg = std::atan2(1.0, 10.0) * 180.0 / 3.141592653589793;
  e.yaw_rate_dps = 12.5;
  e.quality = 0.8;
  e.method_code = 33;
  return e;
}

TEST(VelocityFromEstimate, FreshEstimateIsValid) {
  const auto e = estimate_at(1'000'000'000);
  const VelocityPair p = velocity_from_estimate(&e, 1'000'000'000 + 35'000'000, {100, 0.2});
  EXPECT_TRUE(p.velocity.valid);
  EXPECT_TRUE(p.velocity.yaw_rate_valid);
  EXPECT_DOUBLE_EQ(p.velocity.speed_mps, e.speed_mps);
  EXPECT_NEAR(p.velocity.quality_pct, 80.0, 1e-9);
  EXPECT_TRUE(p.xy.valid);
  EXPECT_EQ(p.xy.age_ms, 35u);
}

TEST(VelocityFromEstimate, StaleEstimateIsSentInvalidWithItsAge) {
  const auto e = estimate_at(1'000'000'000);
  const VelocityPair p = velocity_from_estimate(&e, 1'000'000'000 + 101'000'000, {100, 0.2});
  EXPECT_FALSE(p.velocity.valid || p.velocity.speed_valid || p.velocity.direction_valid || p.velocity.yaw_rate_valid);
  EXPECT_FALSE(p.xy.valid);
  EXPECT_EQ(p.xy.age_ms, 101u);
  // On the wire: flags 0 and values 0, never the old numbers.
  const MessageIds ids;
  const DecodedFrame d = decode(encode_velocity(p.velocity, ids, 0), ids);
  EXPECT_EQ(d.velocity.speed_mps, 0.0);
  EXPECT_EQ(d.velocity.direction_deg, 0.0);
  const DecodedFrame dx = decode(encode_velocity_xy(p.xy, ids, 0), ids);
  EXPECT_FALSE(dx.xy.valid);
  EXPECT_EQ(dx.xy.vx_mps, 0.0);
  EXPECT_EQ(dx.xy.age_ms, 101u);
  // Even if the caller sets values on an invalid message, they are not sent.
  VelocityMsg sloppy;
  sloppy.speed_mps = 33.0;
  EXPECT_EQ(decode(encode_velocity(sloppy, ids, 0), ids).velocity.speed_mps, 0.0);
}

TEST(VelocityFromEstimate, NoEstimateYet) {
  const VelocityPair p = velocity_from_estimate(nullptr, 5, {100, 0.2});
  EXPECT_FALSE(p.velocity.valid);
  EXPECT_FALSE(p.xy.valid);
  EXPECT_EQ(p.xy.age_ms, 65535u);
}

TEST(VelocityFromEstimate, EachQuantityHasItsOwnAvailability) {
  auto e = estimate_at(0);
  e.has_speed = false;  // direction but no speed
  e.has_yaw_rate = false;
  e.has_velocity_xy = false;
  VelocityPair p = velocity_from_estimate(&e, 0, {100, 0.2});
  EXPECT_FALSE(p.velocity.valid);
  EXPECT_FALSE(p.velocity.speed_valid);
  EXPECT_TRUE(p.velocity.direction_valid);
  EXPECT_FALSE(p.velocity.yaw_rate_valid);
  EXPECT_FALSE(p.xy.valid);
  EXPECT_EQ(p.velocity.speed_mps, 0.0);

  auto standstill = estimate_at(0);
  standstill.has_direction = false;
  standstill.speed_mps = standstill.vx_mps = standstill.vy_mps = 0.0;
  p = velocity_from_estimate(&standstill, 0, {100, 0.2});
  EXPECT_TRUE(p.velocity.speed_valid);
  EXPECT_FALSE(p.velocity.direction_valid);
  EXPECT_FALSE(p.velocity.valid);
  EXPECT_TRUE(p.xy.valid) << "vx, vy are known at standstill without a direction";
}

TEST(VelocityFromEstimate, OutOfRangeOrNonFiniteIsInvalidNotClamped) {
  auto e = estimate_at(0);
  e.speed_mps = 90.0;  // above GVS_Speed's 81.91 m/s
  e.yaw_rate_dps = 300.0;
  e.vx_mps = std::numeric_limits<double>::quiet_NaN();
  const VelocityPair p = velocity_from_estimate(&e, 0, {100, 0.2});
  EXPECT_FALSE(p.velocity.speed_valid);
  EXPECT_FALSE(p.velocity.yaw_rate_valid);
  EXPECT_TRUE(p.velocity.direction_valid);
  EXPECT_FALSE(p.xy.valid);
}

TEST(VelocityFromEstimate, LowQualityGoesOutWithEveryValidBitZeroButItsQualityAndAge) {
  auto e = estimate_at(1'000'000'000);
  e.quality = 0.15;  // below the default min_quality 0.3
  const VelocityPair p = velocity_from_estimate(&e, 1'000'000'000 + 12'000'000, {100, 0.2});
  EXPECT_FALSE(p.velocity.valid || p.velocity.speed_valid || p.velocity.direction_valid || p.velocity.yaw_rate_valid);
  EXPECT_FALSE(p.xy.valid);
  EXPECT_TRUE(p.fresh) << "doubtful is not stale";
  EXPECT_EQ(p.xy.age_ms, 12u);
  EXPECT_NEAR(p.velocity.quality_pct, 15.0, 1e-9);
  // On the wire: flags 0, values 0, GVS_Quality 15 %, GVS_Age 12 ms.
  const MessageIds ids;
  const DecodedFrame d = decode(encode_velocity(p.velocity, ids, 0), ids);
  EXPECT_FALSE(d.velocity.valid || d.velocity.speed_valid || d.velocity.direction_valid || d.velocity.yaw_rate_valid);
  EXPECT_EQ(d.velocity.speed_mps, 0.0);
  EXPECT_EQ(d.velocity.direction_deg, 0.0);
  EXPECT_EQ(d.velocity.yaw_rate_dps, 0.0);
  EXPECT_EQ(d.velocity.quality_pct, 15.0);
  const DecodedFrame dx = decode(encode_velocity_xy(p.xy, ids, 0), ids);
  EXPECT_FALSE(dx.xy.valid);
  EXPECT_EQ(dx.xy.vx_mps, 0.0);
  EXPECT_EQ(dx.xy.vy_mps, 0.0);
  EXPECT_EQ(dx.xy.age_ms, 12u);
}

TEST(VelocityFromEstimate, QualityAtTheThresholdIsValid) {
  auto e = estimate_at(0);
  e.quality = 0.2;
  VelocityPair p = velocity_from_estimate(&e, 0, {100, 0.2});
  EXPECT_TRUE(p.velocity.valid && p.velocity.speed_valid && p.velocity.direction_valid && p.velocity.yaw_rate_valid);
  EXPECT_TRUE(p.xy.valid);
  e.quality = std::nextafter(0.2, 0.0);  // the largest quality below it
  p = velocity_from_estimate(&e, 0, {100, 0.2});
  EXPECT_FALSE(p.velocity.speed_valid || p.velocity.direction_valid || p.velocity.yaw_rate_valid || p.xy.valid);
  e.quality = std::numeric_limits<double>::quiet_NaN();
  p = velocity_from_estimate(&e, 0, {100, 0.0});
  EXPECT_FALSE(p.velocity.speed_valid || p.xy.valid) << "a NaN quality is never good enough";
  EXPECT_EQ(p.velocity.quality_pct, 0.0);
  e.quality = 0.05;
  p = velocity_from_estimate(&e, 0, {100, 0.0});
  EXPECT_TRUE(p.velocity.valid) << "min_quality 0 lets every quality through";
}

TEST(VelocityFromEstimate, ImplausibleEstimateGoesOutInvalid) {
  const auto e = estimate_at(0);
  const VelocityPair p = velocity_from_estimate(&e, 3'000'000, {100, 0.2}, false);
  EXPECT_FALSE(p.velocity.valid || p.velocity.speed_valid || p.velocity.direction_valid || p.velocity.yaw_rate_valid);
  EXPECT_FALSE(p.xy.valid);
  EXPECT_TRUE(p.fresh);
  EXPECT_NEAR(p.velocity.quality_pct, 80.0, 1e-9);
  EXPECT_EQ(p.xy.age_ms, 3u);
}

TEST(Encoder, EstimateFramesPackWhatTheRuleDecides) {
  auto e = estimate_at(0);
  e.quality = 0.3;
  Encoder enc({});
  const ValidityRule strict{100, 0.5};
  const ValidityRule lenient{100, 0.25};
  CanFrame v, xy;
  VelocityPair p = enc.estimate_frames(&e, 0, strict, true, v, xy);
  EXPECT_FALSE(p.velocity.valid);
  EXPECT_FALSE(decode(v, enc.ids()).velocity.valid);
  EXPECT_FALSE(decode(xy, enc.ids()).xy.valid);
  p = enc.estimate_frames(&e, 0, lenient, true, v, xy);
  EXPECT_TRUE(p.velocity.valid);
  EXPECT_TRUE(decode(v, enc.ids()).velocity.valid);
  EXPECT_TRUE(decode(xy, enc.ids()).xy.valid);
  EXPECT_EQ(decode(v, enc.ids()).counter, 1) << "one alive counter step per call";
  p = enc.estimate_frames(&e, 0, lenient, false, v, xy);
  EXPECT_FALSE(p.velocity.valid);
  EXPECT_FALSE(decode(v, enc.ids()).velocity.valid) << "not plausible";
  p = enc.estimate_frames(&e, 101'000'000, lenient, true, v, xy);
  EXPECT_FALSE(p.fresh);
  EXPECT_FALSE(decode(v, enc.ids()).velocity.valid) << "stale";
  EXPECT_EQ(decode(xy, enc.ids()).xy.age_ms, 101u);
  p = enc.estimate_frames(nullptr, 0, lenient, true, v, xy);
  EXPECT_FALSE(decode(v, enc.ids()).velocity.valid);
  EXPECT_EQ(decode(xy, enc.ids()).xy.age_ms, 65535u) << "no estimate yet";
}

TEST(Decode, RejectsForeignAndMalformedFrames) {
  const MessageIds ids;
  Encoder enc({});
  CanFrame f = enc.velocity({});
  EXPECT_EQ(decode(f, ids).status, DecodeStatus::Ok);
  CanFrame ext = f;
  ext.extended = true;
  EXPECT_EQ(decode(ext, ids).status, DecodeStatus::NotOurs);
  CanFrame shortf = f;
  shortf.len = 4;
  EXPECT_EQ(decode(shortf, ids).status, DecodeStatus::BadLength);
  CanFrame bad = f;
  bad.data[3] ^= 0x10;
  EXPECT_EQ(decode(bad, ids).status, DecodeStatus::BadCrc);
  CanFrame other = f;
  other.id = 0x123;
  EXPECT_EQ(decode(other, ids).status, DecodeStatus::NotOurs);
}

}  // namespace
}  // namespace gvs::can
