// The gvs CAN messages as data: every signal's bits, scale, offset, range and
// unit. This table and can/gvs.dbc describe the same bits; the test
// tests/can/dbc_crosscheck_test.cpp parses the DBC and fails on any
// difference, so neither can drift. All signals are Intel (little-endian)
// byte order; start bits are DBC start bits (the signal's least significant
// bit, counted from bit 0 of byte 0).
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <string_view>

#include "gvs/can/frame.hpp"

namespace gvs::can {

struct SignalSpec {
  std::string_view name;
  std::uint8_t start_bit = 0;
  std::uint8_t length = 1;
  bool is_signed = false;
  double scale = 1.0;   ///< physical = raw * scale + offset
  double offset = 0.0;
  double minimum = 0.0;  ///< physical range the sender uses
  double maximum = 0.0;
  std::string_view unit;
};

enum class MessageKind : std::uint8_t { Velocity = 0, VelocityXy = 1, Status = 2, Timing = 3, RideHeight = 4 };
inline constexpr std::size_t kMessageKindCount = 5;

struct MessageSpec {
  MessageKind kind;
  std::string_view name;
  std::uint32_t id_offset;  ///< CAN ID = base ID + id_offset
  std::uint32_t period_ms;
  std::span<const SignalSpec> signals;
};

/// Default base ID: GVS_Velocity 0x300, GVS_VelocityXY 0x301, GVS_Status 0x302, GVS_Timing 0x303,
/// GVS_RideHeight 0x304.
inline constexpr std::uint32_t kDefaultBaseId = 0x300;

// Every message starts with the E2E header: signal 0 = CRC, signal 1 = alive counter.
inline constexpr std::size_t kSigCrc = 0;
inline constexpr std::size_t kSigCounter = 1;

// clang-format off
inline constexpr SignalSpec kVelocitySignals[] = {
    {"GVS_CRC",            0,  8, false, 1.0,  0.0,    0.0,   255.0, ""},
    {"GVS_Counter",        8,  4, false, 1.0,  0.0,    0.0,    15.0, ""},
    {"GVS_Valid",         12,  1, false, 1.0,  0.0,    0.0,     1.0, ""},
    {"GVS_SpeedValid",    13,  1, false, 1.0,  0.0,    0.0,     1.0, ""},
    {"GVS_DirectionValid",14,  1, false, 1.0,  0.0,    0.0,     1.0, ""},
    {"GVS_YawRateValid",  15,  1, false, 1.0,  0.0,    0.0,     1.0, ""},
    {"GVS_Speed",         16, 13, false, 0.01, 0.0,    0.0,    81.91, "m/s"},
    {"GVS_Direction",     29, 16, true,  0.01, 0.0, -180.0,   180.0, "deg"},
    {"GVS_YawRate",       45, 12, true,  0.1,  0.0, -204.7,   204.7, "deg/s"},
    {"GVS_Quality",       57,  7, false, 1.0,  0.0,    0.0,   100.0, "%"},
};
namespace sig_velocity {
inline constexpr std::size_t kValid = 2, kSpeedValid = 3, kDirectionValid = 4, kYawRateValid = 5,
                             kSpeed = 6, kDirection = 7, kYawRate = 8, kQuality = 9;
}

inline constexpr SignalSpec kVelocityXySignals[] = {
    {"GVS_CRC",      0,  8, false, 1.0,   0.0,      0.0,     255.0, ""},
    {"GVS_Counter",  8,  4, false, 1.0,   0.0,      0.0,      15.0, ""},
    {"GVS_Valid",   12,  1, false, 1.0,   0.0,      0.0,       1.0, ""},
    {"GVS_ScaleSource", 13, 2, false, 1.0, 0.0,     0.0,       3.0, ""},
    {"GVS_Vx",      16, 16, true,  0.005, 0.0, -163.835,   163.835, "m/s"},
    {"GVS_Vy",      32, 16, true,  0.005, 0.0, -163.835,   163.835, "m/s"},
    {"GVS_Age",     48, 16, false, 1.0,   0.0,      0.0,   65535.0, "ms"},
};
namespace sig_velocity_xy {
inline constexpr std::size_t kValid = 2, kScaleSource = 3, kVx = 4, kVy = 5, kAge = 6;
}

// Fault signals occupy bits 16..31; fault bit k of StatusMsg::faults is the
// signal whose start bit is 16 + k (see FaultBit in codec.hpp).
inline constexpr std::uint8_t kFaultFirstBit = 16;
inline constexpr SignalSpec kStatusSignals[] = {
    {"GVS_CRC",                   0, 8, false, 1.0, 0.0, 0.0, 255.0, ""},
    {"GVS_Counter",               8, 4, false, 1.0, 0.0, 0.0,  15.0, ""},
    {"GVS_State",                12, 4, false, 1.0, 0.0, 0.0,  15.0, ""},
    {"GVS_FaultCamera",          16, 1, false, 1.0, 0.0, 0.0,   1.0, ""},
    {"GVS_FaultEstimateStale",   17, 1, false, 1.0, 0.0, 0.0,   1.0, ""},
    {"GVS_FaultRingOverrun",     18, 1, false, 1.0, 0.0, 0.0,   1.0, ""},
    {"GVS_FaultDeadlineMiss",    19, 1, false, 1.0, 0.0, 0.0,   1.0, ""},
    {"GVS_FaultCanBusOff",       20, 1, false, 1.0, 0.0, 0.0,   1.0, ""},
    {"GVS_FaultCanErrorPassive", 21, 1, false, 1.0, 0.0, 0.0,   1.0, ""},
    {"GVS_FaultCanController",   22, 1, false, 1.0, 0.0, 0.0,   1.0, ""},
    {"GVS_FaultCanInterfaceDown",23, 1, false, 1.0, 0.0, 0.0,   1.0, ""},
    {"GVS_FaultCanSendError",    24, 1, false, 1.0, 0.0, 0.0,   1.0, ""},
    {"GVS_FaultLight",           25, 1, false, 1.0, 0.0, 0.0,   1.0, ""},
    {"GVS_FaultNoRealtime",      26, 1, false, 1.0, 0.0, 0.0,   1.0, ""},
    {"GVS_FaultImplausible",     27, 1, false, 1.0, 0.0, 0.0,   1.0, ""},
    {"GVS_FaultScaleUncorrected",28, 1, false, 1.0, 0.0, 0.0,   1.0, ""},
    {"GVS_DroppedFrames",        32, 8, false, 1.0, 0.0, 0.0, 255.0, ""},
    {"GVS_RingOverruns",         40, 8, false, 1.0, 0.0, 0.0, 255.0, ""},
    {"GVS_CanSendErrors",        48, 8, false, 1.0, 0.0, 0.0, 255.0, ""},
    {"GVS_Method",               56, 8, false, 1.0, 0.0, 0.0, 255.0, ""},
};
namespace sig_status {
inline constexpr std::size_t kState = 2, kFirstFault = 3, kFaultCount = 13, kDroppedFrames = 16,
                             kRingOverruns = 17, kCanSendErrors = 18, kMethod = 19;
}

inline constexpr SignalSpec kTimingSignals[] = {
    {"GVS_CRC",            0,  8, false, 1.0, 0.0, 0.0,   255.0, ""},
    {"GVS_Counter",        8,  4, false, 1.0, 0.0, 0.0,    15.0, ""},
    {"GVS_Exposure",      16, 16, false, 1.0, 0.0, 0.0, 65535.0, "us"},
    {"GVS_ProcessingTime",32, 16, false, 1.0, 0.0, 0.0, 65535.0, "us"},
    {"GVS_LateWakeups",   48,  8, false, 1.0, 0.0, 0.0,   255.0, ""},
};
namespace sig_timing {
inline constexpr std::size_t kExposure = 2, kProcessingTime = 3, kLateWakeups = 4;
}

// The camera's height above the ground and the ground plane's tilt at the
// sensor (ISO 8855: pitch + nose down, roll + right side down), and which
// height the speed's scale rests on (GVS_ScaleSource, core::ScaleSource).
inline constexpr SignalSpec kRideHeightSignals[] = {
    {"GVS_CRC",          0,  8, false, 1.0,  0.0,    0.0,   255.0, ""},
    {"GVS_Counter",      8,  4, false, 1.0,  0.0,    0.0,    15.0, ""},
    {"GVS_HeightValid", 12,  1, false, 1.0,  0.0,    0.0,     1.0, ""},
    {"GVS_PitchValid",  13,  1, false, 1.0,  0.0,    0.0,     1.0, ""},
    {"GVS_ScaleSource", 14,  2, false, 1.0,  0.0,    0.0,     3.0, ""},
    {"GVS_Height",      16, 16, false, 0.01, 0.0,    0.0,  655.35, "mm"},
    {"GVS_Pitch",       32, 12, true,  0.01, 0.0, -20.47,   20.47, "deg"},
    {"GVS_Roll",        44, 12, true,  0.01, 0.0, -20.47,   20.47, "deg"},
    {"GVS_HeightAge",   56,  7, false, 1.0,  0.0,    0.0,   127.0, "ms"},
    {"GVS_RollValid",   63,  1, false, 1.0,  0.0,    0.0,     1.0, ""},
};
namespace sig_ride_height {
inline constexpr std::size_t kHeightValid = 2, kPitchValid = 3, kScaleSource = 4, kHeight = 5, kPitch = 6,
                             kRoll = 7, kHeightAge = 8, kRollValid = 9;
}

inline constexpr MessageSpec kMessages[kMessageKindCount] = {
    {MessageKind::Velocity,   "GVS_Velocity",   0, 20,  kVelocitySignals},
    {MessageKind::VelocityXy, "GVS_VelocityXY", 1, 20,  kVelocityXySignals},
    {MessageKind::Status,     "GVS_Status",     2, 100, kStatusSignals},
    {MessageKind::Timing,     "GVS_Timing",     3, 100, kTimingSignals},
    {MessageKind::RideHeight, "GVS_RideHeight", 4, 20,  kRideHeightSignals},
};
// clang-format on

constexpr const MessageSpec& message_spec(MessageKind kind) {
  return kMessages[static_cast<std::size_t>(kind)];
}

/// Codes of GVS_State (VAL_ table in the DBC).
enum class SensorState : std::uint8_t {
  Init = 0,      ///< starting: no estimate yet
  Running = 1,   ///< estimates flowing
  Degraded = 2,  ///< running, but the current estimate is invalid or stale
  Fault = 3,     ///< camera or CAN fault: no usable output
  Stopping = 4,  ///< shutting down
};
std::string_view state_name(std::uint8_t code) noexcept;

// --- Bit access (Intel byte order) -----------------------------------------

/// The signal's raw bits, unsigned (not sign-extended).
std::uint64_t get_raw_bits(const CanFrame& frame, const SignalSpec& sig) noexcept;
/// The signal's raw value, sign-extended when the signal is signed.
std::int64_t get_raw(const CanFrame& frame, const SignalSpec& sig) noexcept;
/// Writes the low `length` bits of `raw` (two's complement for signed signals).
void set_raw(CanFrame& frame, const SignalSpec& sig, std::int64_t raw) noexcept;
/// raw * scale + offset.
double to_physical(const SignalSpec& sig, std::int64_t raw) noexcept;
/// Nearest raw value of a physical value, clamped to [minimum, maximum].
/// NaN gives the raw value of 0.0 clamped into range.
std::int64_t to_raw(const SignalSpec& sig, double physical) noexcept;
/// True when `physical` is finite and lies in [minimum, maximum] (within half a step).
bool in_range(const SignalSpec& sig, double physical) noexcept;

}  // namespace gvs::can
