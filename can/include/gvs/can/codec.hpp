// Packing and unpacking of the gvs messages (physical values <-> frames),
// with E2E protection. No allocation, no exceptions after construction.
#pragma once

#include <cmath>
#include <cstdint>
#include <optional>

#include "gvs/can/frame.hpp"
#include "gvs/can/signals.hpp"

namespace gvs::can {

/// GVS_Velocity. A value whose *_valid flag is false is sent as 0 and must be ignored.
struct VelocityMsg {
  bool valid = false;  ///< GVS_Valid: speed and direction both valid
  bool speed_valid = false;
  bool direction_valid = false;
  bool yaw_rate_valid = false;
  double speed_mps = 0.0;
  double direction_deg = 0.0;  ///< ISO 8855: atan2(vy, vx), 0 = straight ahead, + = to the left
  double yaw_rate_dps = 0.0;   ///< ISO 8855: + = counter-clockwise seen from above
  double quality_pct = 0.0;    ///< estimator quality 0..100 %
};

/// GVS_ScaleSource's codes (core::ScaleSource): which height the speed's
/// scale rests on.
enum class ScaleSourceCode : std::uint8_t { Nominal = 0, LaserDots = 1, External = 2 };

/// GVS_VelocityXY. Vx, Vy are 0 when !valid.
struct VelocityXyMsg {
  bool valid = false;
  double vx_mps = 0.0;  ///< vehicle x, forward
  double vy_mps = 0.0;  ///< vehicle y, left
  std::uint32_t age_ms = 65535;  ///< age of the estimate at send time; 65535 = none / >= 65.535 s
  ScaleSourceCode scale_source = ScaleSourceCode::Nominal;  ///< of Vx, Vy and GVS_Speed (sent even when !valid)
};

/// Fault bits of GVS_Status (bit k = DBC signal at start bit 16 + k).
enum FaultBit : std::uint16_t {
  kFaultCamera = 1u << 0,              ///< no frames from the camera, or a source error
  kFaultEstimateStale = 1u << 1,       ///< newest estimate older than the stale limit
  kFaultRingOverrun = 1u << 2,         ///< the frame ring overflowed since the last status
  kFaultDeadlineMiss = 1u << 3,        ///< the CAN sender woke up late since the last status
  kFaultCanBusOff = 1u << 4,           ///< controller is (or was, since the last status) bus-off
  kFaultCanErrorPassive = 1u << 5,     ///< controller error-passive
  kFaultCanController = 1u << 6,       ///< controller problem (overflow, warning level)
  kFaultCanInterfaceDown = 1u << 7,    ///< interface was down/removed since the last status
  kFaultCanSendError = 1u << 8,        ///< a send failed (ENOBUFS, EAGAIN, ...) since the last status
  kFaultLight = 1u << 9,               ///< an LED ring / strobe write failed or a plan was refused since the last status
  kFaultNoRealtime = 1u << 10,         ///< running without real-time scheduling (desk mode)
  kFaultImplausible = 1u << 11,        ///< an estimate was held back as physically implausible since the last status
  kFaultScaleUncorrected = 1u << 12,   ///< the newest speed's scale rests on the nominal height (no height measured)
};

struct StatusMsg {
  SensorState state = SensorState::Init;
  std::uint16_t faults = 0;           ///< FaultBit mask
  std::uint8_t dropped_frames = 0;    ///< running count modulo 256
  std::uint8_t ring_overruns = 0;     ///< running count modulo 256
  std::uint8_t can_send_errors = 0;   ///< running count modulo 256
  std::uint8_t method = 0;            ///< GVS_Method: the newest estimate's method code (BusEstimate::method_code)
};

/// GVS_RideHeight. A value whose valid flag is false is sent as 0.
struct RideHeightMsg {
  bool height_valid = false;
  bool pitch_valid = false;
  bool roll_valid = false;
  ScaleSourceCode scale_source = ScaleSourceCode::Nominal;
  double height_mm = 0.0;  ///< camera above the ground
  double pitch_deg = 0.0;  ///< ISO 8855: + = nose down
  double roll_deg = 0.0;   ///< ISO 8855: + = right side down
  std::uint32_t age_ms = 127;  ///< age of the measurement at send time; saturates at 127 (= none or older)
};

struct TimingMsg {
  std::uint32_t exposure_us = 0;          ///< saturates at 65535
  std::uint32_t processing_time_us = 0;   ///< saturates at 65535
  std::uint8_t late_wakeups = 0;          ///< running count modulo 256
};

/// The CAN IDs of the messages for one base ID.
struct MessageIds {
  std::uint32_t base = kDefaultBaseId;

  [[nodiscard]] constexpr std::uint32_t id(MessageKind kind) const {
    return base + message_spec(kind).id_offset;
  }
  /// The message kind of a standard CAN ID, if it is one of ours.
  [[nodiscard]] std::optional<MessageKind> kind_of(std::uint32_t can_id) const noexcept;
};

/// Throws std::invalid_argument (saying what to do) if the base ID leaves no
/// room for the five standard 11-bit IDs base..base+4.
void validate_base_id(std::uint32_t base_id);

// Pure packing: frame with E2E header (counter, CRC) from physical values.
CanFrame encode_velocity(const VelocityMsg& m, const MessageIds& ids, std::uint8_t counter) noexcept;
CanFrame encode_velocity_xy(const VelocityXyMsg& m, const MessageIds& ids, std::uint8_t counter) noexcept;
CanFrame encode_status(const StatusMsg& m, const MessageIds& ids, std::uint8_t counter) noexcept;
CanFrame encode_timing(const TimingMsg& m, const MessageIds& ids, std::uint8_t counter) noexcept;
CanFrame encode_ride_height(const RideHeightMsg& m, const MessageIds& ids, std::uint8_t counter) noexcept;

/// The newest estimate as the bus sees it, filled by the daemon from the
/// estimator's output. A quantity without its has_ flag is meaningless.
struct BusEstimate {
  std::int64_t t_ns = 0;  ///< the time the estimate describes, on the sender's clock
  bool has_speed = false;
  bool has_direction = false;
  bool has_yaw_rate = false;
  bool has_velocity_xy = false;  ///< vx, vy known (speed and direction, or standing still)
  double speed_mps = 0.0;
  double direction_deg = 0.0;  ///< ISO 8855: atan2(vy, vx)
  double yaw_rate_dps = 0.0;
  double vx_mps = 0.0;
  double vy_mps = 0.0;
  double quality = 0.0;         ///< [0, 1]
  std::uint8_t method_code = 0; ///< GVS_Method (docs/can-interface.md, "Method codes")
  ScaleSourceCode scale_source = ScaleSourceCode::Nominal;  ///< the height speed, vx, vy are scaled with
  bool has_height = false;  ///< the camera's height, measured for this estimate's instant
  double height_mm = 0.0;
  bool has_pitch = false;  ///< measured for this estimate's instant
  double pitch_deg = 0.0;
  bool has_roll = false;  ///< measured for this estimate's instant
  double roll_deg = 0.0;
};

/// When an estimate may go out as valid (docs/can-interface.md, "Validity").
struct ValidityRule {
  std::int64_t stale_after_ms = 50;  ///< older (or from the future by more) -> every Valid bit 0
  double min_quality = 0.3;          ///< lower quality (or NaN) -> every Valid bit 0
};

/// The rule's quality condition: a finite quality of at least `min_quality`.
[[nodiscard]] inline bool quality_passes(double quality, double min_quality) noexcept {
  return std::isfinite(quality) && quality >= min_quality;
}

/// The two velocity messages for the newest estimate (or none), `now_ns` on
/// the estimate's clock. A quantity's Valid bit is 1 only when the estimate
/// has it, it lies in its DBC range, the estimate is fresh (`stale_after_ms`),
/// its quality is >= `min_quality` and the daemon found it `plausible`;
/// otherwise the bit is 0 and the value 0. GVS_Quality always carries the
/// estimate's quality and GVS_Age its age. Quantities out of the DBC range are
/// flagged invalid, never clamped and passed off as valid.
struct VelocityPair {
  VelocityMsg velocity;
  VelocityXyMsg xy;
  bool fresh = false;  ///< an estimate within the stale limit (GVS_FaultEstimateStale = !fresh)
};
VelocityPair velocity_from_estimate(const BusEstimate* estimate, std::int64_t now_ns, const ValidityRule& rule,
                                    bool plausible = true) noexcept;

/// GVS_RideHeight for the newest estimate (nullptr = none yet): height and
/// tilt valid when the estimate carries them, they lie in their DBC range
/// and the estimate is fresh (`rule.stale_after_ms`). The estimator's quality
/// and the velocity's plausibility do not gate them: the height is measured
/// by other means (docs/can-interface.md, "GVS_RideHeight").
RideHeightMsg ride_height_from_estimate(const BusEstimate* estimate, std::int64_t now_ns,
                                        const ValidityRule& rule) noexcept;

struct EncoderConfig {
  std::uint32_t base_id = kDefaultBaseId;
};

/// Keeps one alive counter per message; the CAN sender's only codec object.
class Encoder {
 public:
  /// Throws std::invalid_argument for a bad base ID.
  explicit Encoder(const EncoderConfig& config);

  [[nodiscard]] const MessageIds& ids() const { return ids_; }
  [[nodiscard]] const EncoderConfig& config() const { return config_; }

  CanFrame velocity(const VelocityMsg& m) noexcept;
  CanFrame velocity_xy(const VelocityXyMsg& m) noexcept;
  CanFrame status(const StatusMsg& m) noexcept;
  CanFrame timing(const TimingMsg& m) noexcept;
  CanFrame ride_height(const RideHeightMsg& m) noexcept;

  /// Both 20 ms frames for the newest estimate (nullptr = none yet) under
  /// `rule` (velocity_from_estimate); returns what they carry. gvsd's sender
  /// packs its velocity messages with this call and nothing else.
  VelocityPair estimate_frames(const BusEstimate* estimate, std::int64_t now_ns, const ValidityRule& rule,
                               bool plausible, CanFrame& velocity_out, CanFrame& xy_out) noexcept;

 private:
  std::uint8_t next_counter(MessageKind kind) noexcept;

  EncoderConfig config_;
  MessageIds ids_;
  std::uint8_t counters_[kMessageKindCount] = {};
};

// --- Decoding ------------------------------------------------------------------

enum class DecodeStatus : std::uint8_t {
  Ok,
  NotOurs,    ///< extended, remote, error frame or an ID that is not a gvs message
  BadLength,  ///< a gvs ID with DLC != 8
  BadCrc,     ///< a gvs ID whose byte 0 does not match the CRC (values still decoded)
};

struct DecodedFrame {
  DecodeStatus status = DecodeStatus::NotOurs;
  MessageKind kind = MessageKind::Velocity;  ///< meaningful unless NotOurs
  std::uint8_t counter = 0;
  VelocityMsg velocity;  ///< filled for kind == Velocity
  VelocityXyMsg xy;      ///< filled for kind == VelocityXy
  StatusMsg status_msg;  ///< filled for kind == Status
  TimingMsg timing;      ///< filled for kind == Timing
  RideHeightMsg ride;    ///< filled for kind == RideHeight
};

/// Decodes any frame; never throws, accepts arbitrary input.
DecodedFrame decode(const CanFrame& frame, const MessageIds& ids) noexcept;

}  // namespace gvs::can
