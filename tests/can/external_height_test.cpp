// An external distance sensor's height: its signal read out of a foreign
// frame (Intel and Motorola, as DBC files describe them) and the height at
// a frame's instant from the samples received.
#include <gtest/gtest.h>

#include <limits>

#include "gvs/can/foreign_signal.hpp"
#include "gvs/can/height_receiver.hpp"

namespace gvs::can {
namespace {

CanFrame frame(std::uint32_t id, std::array<std::uint8_t, 8> data, std::uint8_t len = 8) {
  CanFrame f;
  f.id = id;
  f.len = len;
  f.data = data;
  return f;
}

TEST(ForeignSignal, MotorolaAsTheHeaderExample) {
  // SG_ Height : 7|16@0+ (0.01,0): frame 520#1770000000000000 -> 60.00 mm
  const ForeignSignal s{.can_id = 0x520, .start_bit = 7, .length = 16, .big_endian = true, .scale = 0.01};
  validate(s);
  const auto v = read_signal(frame(0x520, {0x17, 0x70, 0, 0, 0, 0, 0, 0}), s);
  ASSERT_TRUE(v);
  EXPECT_NEAR(*v, 60.0, 1e-9);
}

TEST(ForeignSignal, IntelSignedWithOffset) {
  // SG_ Height : 16|12@1- (0.05,60): raw -40 -> 58 mm; raw 0xFD8 is -40 in 12 bits
  const ForeignSignal s{.can_id = 0x123, .start_bit = 16, .length = 12, .is_signed = true, .scale = 0.05,
                        .offset = 60.0};
  const auto v = read_signal(frame(0x123, {0xAA, 0xBB, 0xD8, 0x0F, 0, 0, 0, 0}), s);
  ASSERT_TRUE(v);
  EXPECT_NEAR(*v, 58.0, 1e-9);
}

TEST(ForeignSignal, MotorolaAcrossThreeBytes) {
  // 12 bits from start bit 3 (Motorola): bits 3..0 of byte 0, then 7..0 of byte 1.
  const ForeignSignal s{.can_id = 0x10, .start_bit = 3, .length = 12, .big_endian = true};
  const auto v = read_signal(frame(0x10, {0xF5, 0x4C, 0, 0, 0, 0, 0, 0}), s);
  ASSERT_TRUE(v);
  EXPECT_EQ(*v, 0x54C);
}

TEST(ForeignSignal, OtherFramesGiveNothing) {
  const ForeignSignal s{.can_id = 0x520, .start_bit = 0, .length = 16};
  EXPECT_FALSE(read_signal(frame(0x521, {}), s));
  CanFrame ext = frame(0x520, {});
  ext.extended = true;
  EXPECT_FALSE(read_signal(ext, s));
  CanFrame remote = frame(0x520, {});
  remote.remote = true;
  EXPECT_FALSE(read_signal(remote, s));
  EXPECT_FALSE(read_signal(frame(0x520, {}, 1), s)) << "a 1-byte frame cannot hold a 16-bit signal";
  EXPECT_TRUE(read_signal(frame(0x520, {}, 2), s));
}

TEST(ForeignSignal, ValidateRefusesSignalsOutsideTheFrame) {
  EXPECT_THROW(validate({.start_bit = 56, .length = 16}), std::invalid_argument);
  EXPECT_THROW(validate({.start_bit = 0, .length = 0}), std::invalid_argument);
  EXPECT_THROW(validate({.start_bit = 0, .length = 33}), std::invalid_argument);
  EXPECT_THROW(validate({.start_bit = 63, .length = 16, .big_endian = true}), std::invalid_argument);
  EXPECT_THROW(validate({.can_id = 0x800, .start_bit = 0, .length = 8}), std::invalid_argument);
  EXPECT_NO_THROW(validate({.can_id = 0x800, .extended = true, .start_bit = 0, .length = 8}));
  EXPECT_THROW(validate({.start_bit = 0, .length = 8, .scale = 0.0}), std::invalid_argument);
}

constexpr std::int64_t kMs = 1'000'000;

TEST(HeightHistory, InterpolatesBetweenSamplesAtTheFramesInstant) {
  HeightHistory h;
  h.add(100 * kMs, 60.0);
  h.add(102 * kMs, 61.0);
  h.add(104 * kMs, 63.0);
  EXPECT_NEAR(*h.at(101 * kMs, 5 * kMs), 60.5, 1e-12);
  EXPECT_NEAR(*h.at(103500000, 5 * kMs), 62.5, 1e-12);
  EXPECT_NEAR(*h.at(104 * kMs, 5 * kMs), 63.0, 1e-12);
}

TEST(HeightHistory, HoldsTheNewestOnlyWithinTheGap) {
  HeightHistory h;
  h.add(100 * kMs, 60.0);
  EXPECT_NEAR(*h.at(104 * kMs, 5 * kMs), 60.0, 1e-12);
  EXPECT_FALSE(h.at(106 * kMs, 5 * kMs)) << "a silent sensor must leave the scale uncorrected";
  EXPECT_FALSE(h.at(99 * kMs, 5 * kMs)) << "before every sample kept";
}

TEST(HeightHistory, NoInterpolationAcrossAGap) {
  HeightHistory h;
  h.add(100 * kMs, 60.0);
  h.add(120 * kMs, 64.0);
  EXPECT_FALSE(h.at(110 * kMs, 5 * kMs));
}

TEST(HeightHistory, IgnoresNonsenseAndOutOfOrderSamples) {
  HeightHistory h;
  EXPECT_TRUE(h.add(100 * kMs, 60.0));
  EXPECT_FALSE(h.add(101 * kMs, std::numeric_limits<double>::quiet_NaN()));
  EXPECT_FALSE(h.add(101 * kMs, 0.0));
  EXPECT_FALSE(h.add(99 * kMs, 61.0));
  EXPECT_EQ(h.size(), 1u);
}

TEST(HeightHistory, KeepsTheNewestSixtyFour) {
  HeightHistory h;
  for (int i = 0; i < 100; ++i) h.add(i * kMs, 50.0 + i);
  EXPECT_EQ(h.size(), 64u);
  EXPECT_FALSE(h.at(30 * kMs, 5 * kMs));
  EXPECT_NEAR(*h.at(50 * kMs, 5 * kMs), 100.0, 1e-12);
}

TEST(HeightReceiver, NamesTheInterfaceItCannotOpen) {
  try {
    HeightReceiver r("gvsnosuch0", ForeignSignal{.can_id = 0x520});
    FAIL() << "opened a CAN interface that does not exist";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("gvsnosuch0"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace gvs::can
