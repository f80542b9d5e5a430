// can/gvs.dbc and the codec describe the same bits: parsed from the DBC here,
// compared with the code's signal table, and every signal packed by one side
// and unpacked by the other.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <random>
#include <set>
#include <string>

#include "dbc_file.hpp"
#include "gvs/can/codec.hpp"
#include "gvs/can/e2e.hpp"
#include "gvs/can/signals.hpp"
#include "gvs/core/method.hpp"

namespace gvs::can {
namespace {

using test::DbcFile;
using test::DbcMessage;
using test::DbcSignal;

const DbcFile& dbc() {
  static const DbcFile file = test::read_dbc(GVS_CAN_DBC);
  return file;
}

const DbcSignal& dbc_signal(const DbcMessage& m, std::string_view name) {
  for (const DbcSignal& s : m.signals) {
    if (s.name == name) return s;
  }
  throw std::runtime_error("signal " + std::string(name) + " not in DBC message " + m.name);
}

TEST(DbcCrossCheck, SameMessagesIdsAndCycleTimes) {
  ASSERT_EQ(dbc().messages.size(), kMessageKindCount);
  const MessageIds ids{kDefaultBaseId};
  for (const MessageSpec& spec : kMessages) {
    const DbcMessage* m = dbc().find(std::string(spec.name));
    ASSERT_NE(m, nullptr) << spec.name;
    EXPECT_EQ(m->id, ids.id(spec.kind)) << spec.name;
    EXPECT_EQ(m->dlc, 8) << spec.name;
    EXPECT_EQ(m->sender, "GVS");
    EXPECT_EQ(m->cycle_time_ms, static_cast<int>(spec.period_ms)) << spec.name;
  }
}

TEST(DbcCrossCheck, SameSignalsBitsScaleSignRangeUnit) {
  for (const MessageSpec& spec : kMessages) {
    const DbcMessage& m = *dbc().find(std::string(spec.name));
    ASSERT_EQ(m.signals.size(), spec.signals.size()) << spec.name;
    for (const SignalSpec& s : spec.signals) {
      SCOPED_TRACE(std::string(spec.name) + "." + std::string(s.name));
      const DbcSignal& d = dbc_signal(m, s.name);
      EXPECT_EQ(d.start_bit, s.start_bit);
      EXPECT_EQ(d.length, s.length);
      EXPECT_TRUE(d.little_endian);
      EXPECT_EQ(d.is_signed, s.is_signed);
      EXPECT_DOUBLE_EQ(d.scale, s.scale);
      EXPECT_DOUBLE_EQ(d.offset, s.offset);
      EXPECT_DOUBLE_EQ(d.minimum, s.minimum);
      EXPECT_DOUBLE_EQ(d.maximum, s.maximum);
      EXPECT_EQ(d.unit, s.unit);
      // The documented range must be representable in the raw bits.
      const double raw_lo = s.is_signed ? -std::ldexp(1.0, s.length - 1) : 0.0;
      const double raw_hi = s.is_signed ? std::ldexp(1.0, s.length - 1) - 1 : std::ldexp(1.0, s.length) - 1;
      EXPECT_GE((s.minimum - s.offset) / s.scale, raw_lo - 1e-9);
      EXPECT_LE((s.maximum - s.offset) / s.scale, raw_hi + 1e-9);
      EXPECT_FALSE(m.comments.at(std::string(s.name)).empty()) << "every signal has a CM_ comment";
    }
  }
}

TEST(DbcCrossCheck, NoOverlappingSignalsAndE2eHeaderFirst) {
  for (const DbcMessage& m : dbc().messages) {
    std::uint64_t used = 0;
    for (const DbcSignal& s : m.signals) {
      for (int b = s.start_bit; b < s.start_bit + s.length; ++b) {
        ASSERT_LT(b, 64) << m.name << "." << s.name;
        EXPECT_EQ((used >> b) & 1u, 0u) << m.name << "." << s.name << " overlaps at bit " << b;
        used |= std::uint64_t{1} << b;
      }
    }
    const DbcSignal& crc = dbc_signal(m, "GVS_CRC");
    const DbcSignal& counter = dbc_signal(m, "GVS_Counter");
    EXPECT_EQ(crc.start_bit, 0);
    EXPECT_EQ(crc.length, 8);
    EXPECT_EQ(counter.start_bit, 8);
    EXPECT_EQ(counter.length, 4);
  }
}

// Raw bits written with the DBC's definition are read back by the codec's
// bit access, and the other way round, for every signal.
TEST(DbcCrossCheck, EverySignalPacksAtTheDbcBits) {
  std::mt19937_64 rng(42);
  for (const MessageSpec& spec : kMessages) {
    const DbcMessage& m = *dbc().find(std::string(spec.name));
    for (const SignalSpec& s : spec.signals) {
      SCOPED_TRACE(std::string(spec.name) + "." + std::string(s.name));
      const DbcSignal& d = dbc_signal(m, s.name);
      for (int trial = 0; trial < 50; ++trial) {
        const std::uint64_t mask = (std::uint64_t{1} << s.length) - 1;
        const std::uint64_t bits = trial == 0 ? mask : trial == 1 ? 0 : rng() & mask;
        CanFrame f;
        f.len = 8;
        for (auto& b : f.data) b = static_cast<std::uint8_t>(rng());
        test::dbc_set_bits(f.data.data(), d, bits);
        EXPECT_EQ(get_raw_bits(f, s), bits);
        EXPECT_DOUBLE_EQ(to_physical(s, get_raw(f, s)), test::dbc_physical(f.data.data(), d));
        CanFrame g;
        for (auto& b : g.data) b = static_cast<std::uint8_t>(rng());
        const auto before = g.data;
        set_raw(g, s, static_cast<std::int64_t>(bits));
        EXPECT_EQ(test::dbc_get_bits(g.data.data(), d), bits);
        // No other bit changed.
        for (int b = 0; b < 64; ++b) {
          if (b >= s.start_bit && b < s.start_bit + s.length) continue;
          EXPECT_EQ((g.data[static_cast<std::size_t>(b / 8)] >> (b % 8)) & 1,
                    (before[static_cast<std::size_t>(b / 8)] >> (b % 8)) & 1);
        }
      }
    }
  }
}

// The typed encoders put each physical value in the signal the DBC names.
void expect_signals(const CanFrame& f, const std::string& message, const std::map<std::string, double>& expected) {
  const DbcMessage& m = *dbc().find(message);
  EXPECT_EQ(f.id, m.id);
  std::set<std::string> seen;
  for (const DbcSignal& s : m.signals) {
    if (s.name == "GVS_CRC" || s.name == "GVS_Counter") continue;
    ASSERT_TRUE(expected.count(s.name)) << "test misses " << message << "." << s.name;
    EXPECT_NEAR(test::dbc_physical(f.data.data(), s), expected.at(s.name), s.scale / 2 + 1e-9)
        << message << "." << s.name;
    seen.insert(s.name);
  }
  EXPECT_EQ(seen.size(), expected.size()) << "expected names a signal the DBC lacks";
}

TEST(DbcCrossCheck, TypedEncodersMatchDbc) {
  const MessageIds ids{kDefaultBaseId};
  VelocityMsg v{true, true, true, true, 23.456, -12.34, -57.3, 87.0};
  expect_signals(encode_velocity(v, ids, 3), "GVS_Velocity",
                 {{"GVS_Valid", 1}, {"GVS_SpeedValid", 1}, {"GVS_DirectionValid", 1}, {"GVS_YawRateValid", 1},
                  {"GVS_Speed", 23.456}, {"GVS_Direction", -12.34}, {"GVS_YawRate", -57.3}, {"GVS_Quality", 87}});
  VelocityMsg v2{false, false, true, false, 0.0, 179.99, 0.0, 12.0};
  expect_signals(encode_velocity(v2, ids, 3), "GVS_Velocity",
                 {{"GVS_Valid", 0}, {"GVS_SpeedValid", 0}, {"GVS_DirectionValid", 1}, {"GVS_YawRateValid", 0},
                  {"GVS_Speed", 0}, {"GVS_Direction", 179.99}, {"GVS_YawRate", 0}, {"GVS_Quality", 12}});
  VelocityXyMsg xy{true, 69.444, -3.215, 17, ScaleSourceCode::External};
  expect_signals(encode_velocity_xy(xy, ids, 9), "GVS_VelocityXY",
                 {{"GVS_Valid", 1}, {"GVS_ScaleSource", 2}, {"GVS_Vx", 69.444}, {"GVS_Vy", -3.215}, {"GVS_Age", 17}});
  StatusMsg st{SensorState::Degraded,
               kFaultCamera | kFaultCanBusOff | kFaultNoRealtime | kFaultImplausible | kFaultScaleUncorrected, 201, 7,
               250, 16};
  expect_signals(encode_status(st, ids, 15), "GVS_Status",
                 {{"GVS_State", 2}, {"GVS_FaultCamera", 1}, {"GVS_FaultEstimateStale", 0},
                  {"GVS_FaultRingOverrun", 0}, {"GVS_FaultDeadlineMiss", 0}, {"GVS_FaultCanBusOff", 1},
                  {"GVS_FaultCanErrorPassive", 0}, {"GVS_FaultCanController", 0},
                  {"GVS_FaultCanInterfaceDown", 0}, {"GVS_FaultCanSendError", 0}, {"GVS_FaultLight", 0},
                  {"GVS_FaultNoRealtime", 1}, {"GVS_FaultImplausible", 1}, {"GVS_FaultScaleUncorrected", 1}, {"GVS_DroppedFrames", 201}, {"GVS_RingOverruns", 7},
                  {"GVS_CanSendErrors", 250}, {"GVS_Method", 16}});
  // Every fault bit lands in its own DBC signal.
  const DbcMessage& status = *dbc().find("GVS_Status");
  for (unsigned bit = 0; bit < sig_status::kFaultCount; ++bit) {
    StatusMsg one;
    one.faults = static_cast<std::uint16_t>(1u << bit);
    const CanFrame f = encode_status(one, ids, 0);
    int set = 0;
    for (const DbcSignal& s : status.signals) {
      if (s.name.rfind("GVS_Fault", 0) == 0 && test::dbc_get_bits(f.data.data(), s) == 1) {
        ++set;
        EXPECT_EQ(s.start_bit, static_cast<int>(kFaultFirstBit + bit));
      }
    }
    EXPECT_EQ(set, 1) << "fault bit " << bit;
  }
  TimingMsg t{2500, 4321, 3};
  expect_signals(encode_timing(t, ids, 1), "GVS_Timing",
                 {{"GVS_Exposure", 2500}, {"GVS_ProcessingTime", 4321}, {"GVS_LateWakeups", 3}});
  RideHeightMsg r{true, true, true, ScaleSourceCode::LaserDots, 61.23, -1.47, 0.92, 4};
  expect_signals(encode_ride_height(r, ids, 2), "GVS_RideHeight",
                 {{"GVS_HeightValid", 1}, {"GVS_PitchValid", 1}, {"GVS_RollValid", 1}, {"GVS_ScaleSource", 1},
                  {"GVS_Height", 61.23}, {"GVS_Pitch", -1.47}, {"GVS_Roll", 0.92}, {"GVS_HeightAge", 4}});
  // The roll without the pitch (three dots without dot 0 or 1), its bit the
  // message's last beside the oldest age the 7 bits hold.
  RideHeightMsg roll_only{true, false, true, ScaleSourceCode::LaserDots, 61.23, -1.47, 0.92, 127};
  expect_signals(encode_ride_height(roll_only, ids, 2), "GVS_RideHeight",
                 {{"GVS_HeightValid", 1}, {"GVS_PitchValid", 0}, {"GVS_RollValid", 1}, {"GVS_ScaleSource", 1},
                  {"GVS_Height", 61.23}, {"GVS_Pitch", 0}, {"GVS_Roll", 0.92}, {"GVS_HeightAge", 127}});
  RideHeightMsg none{false, false, false, ScaleSourceCode::Nominal, 61.23, -1.47, 0.92, 127};
  expect_signals(encode_ride_height(none, ids, 2), "GVS_RideHeight",
                 {{"GVS_HeightValid", 0}, {"GVS_PitchValid", 0}, {"GVS_RollValid", 0}, {"GVS_ScaleSource", 0},
                  {"GVS_Height", 0}, {"GVS_Pitch", 0}, {"GVS_Roll", 0}, {"GVS_HeightAge", 127}});
}

TEST(DbcCrossCheck, E2eHeaderReadThroughDbc) {
  Encoder enc({});
  for (int i = 0; i < 20; ++i) {
    const CanFrame f = enc.velocity(VelocityMsg{});
    const DbcMessage& m = *dbc().find("GVS_Velocity");
    EXPECT_EQ(test::dbc_get_bits(f.data.data(), dbc_signal(m, "GVS_Counter")), static_cast<unsigned>(i % 16));
    EXPECT_EQ(test::dbc_get_bits(f.data.data(), dbc_signal(m, "GVS_CRC")), e2e_crc(f, 0x00));
  }
}

TEST(DbcCrossCheck, ValueTablesMatchCode) {
  const DbcMessage& status = *dbc().find("GVS_Status");
  // GVS_Method's codes and words are core's method table (gvs/core/method.hpp).
  const auto& methods = status.value_tables.at("GVS_Method");
  EXPECT_EQ(methods.size(), core::kMethodCount);
  for (const core::MethodInfo& m : core::kMethods) {
    ASSERT_TRUE(methods.count(m.can_code)) << m.word;
    EXPECT_EQ(methods.at(m.can_code), m.word);
  }
  const auto& states = status.value_tables.at("GVS_State");
  for (const auto& [code, text] : states) {
    std::string lower = text;
    for (char& c : lower) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    EXPECT_EQ(state_name(static_cast<std::uint8_t>(code)), lower);
  }
  EXPECT_EQ(states.size(), 5u);
}

}  // namespace
}  // namespace gvs::can
