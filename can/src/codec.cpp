#include "gvs/can/codec.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>
#include <string>

#include "gvs/can/e2e.hpp"

namespace gvs::can {

namespace {

CanFrame blank_frame(const MessageIds& ids, MessageKind kind) {
  CanFrame f;
  f.id = ids.id(kind);
  f.len = 8;
  return f;
}

void put(CanFrame& f, const SignalSpec& sig, double physical) { set_raw(f, sig, to_raw(sig, physical)); }
void put_flag(CanFrame& f, const SignalSpec& sig, bool on) { set_raw(f, sig, on ? 1 : 0); }
void put_count(CanFrame& f, const SignalSpec& sig, std::uint64_t value) {
  const auto max = static_cast<std::uint64_t>(sig.maximum);
  set_raw(f, sig, static_cast<std::int64_t>(std::min(value, max)));
}

double get(const CanFrame& f, const SignalSpec& sig) { return to_physical(sig, get_raw(f, sig)); }
bool get_flag(const CanFrame& f, const SignalSpec& sig) { return get_raw_bits(f, sig) != 0; }
template <typename T>
T get_uint(const CanFrame& f, const SignalSpec& sig) {
  return static_cast<T>(get_raw_bits(f, sig));
}

}  // namespace

std::optional<MessageKind> MessageIds::kind_of(std::uint32_t can_id) const noexcept {
  for (const MessageSpec& m : kMessages) {
    if (can_id == base + m.id_offset) return m.kind;
  }
  return std::nullopt;
}

void validate_base_id(std::uint32_t base_id) {
  const std::uint32_t last = base_id + kMessages[kMessageKindCount - 1].id_offset;
  if (base_id > CanFrame::kMaxStandardId || last > CanFrame::kMaxStandardId) {
    char hex[16];
    std::snprintf(hex, sizeof hex, "%X", base_id);
    throw std::invalid_argument(std::string("CAN base ID 0x") + hex + " leaves no room for the gvs messages base..base+4 in 11-bit IDs; choose a base ID <= 0x7FB");
  }
}

CanFrame encode_velocity(const VelocityMsg& m, const MessageIds& ids, std::uint8_t counter) noexcept {
  using namespace sig_velocity;
  const auto& s = kVelocitySignals;
  CanFrame f = blank_frame(ids, MessageKind::Velocity);
  put_flag(f, s[kValid], m.valid);
  put_flag(f, s[kSpeedValid], m.speed_valid);
  put_flag(f, s[kDirectionValid], m.direction_valid);
  put_flag(f, s[kYawRateValid], m.yaw_rate_valid);
  put(f, s[kSpeed], m.speed_valid ? m.speed_mps : 0.0);
  put(f, s[kDirection], m.direction_valid ? m.direction_deg : 0.0);
  put(f, s[kYawRate], m.yaw_rate_valid ? m.yaw_rate_dps : 0.0);
  put(f, s[kQuality], m.quality_pct);
  e2e_protect(f, counter);
  return f;
}

CanFrame encode_velocity_xy(const VelocityXyMsg& m, const MessageIds& ids, std::uint8_t counter) noexcept {
  using namespace sig_velocity_xy;
  const auto& s = kVelocityXySignals;
  CanFrame f = blank_frame(ids, MessageKind::VelocityXy);
  put_flag(f, s[kValid], m.valid);
  put_count(f, s[kScaleSource], static_cast<std::uint8_t>(m.scale_source));
  put(f, s[kVx], m.valid ? m.vx_mps : 0.0);
  put(f, s[kVy], m.valid ? m.vy_mps : 0.0);
  put_count(f, s[kAge], m.age_ms);
  e2e_protect(f, counter);
  return f;
}

CanFrame encode_status(const StatusMsg& m, const MessageIds& ids, std::uint8_t counter) noexcept {
  using namespace sig_status;
  const auto& s = kStatusSignals;
  CanFrame f = blank_frame(ids, MessageKind::Status);
  put_count(f, s[kState], static_cast<std::uint8_t>(m.state));
  for (std::size_t i = kFirstFault; i < kFirstFault + kFaultCount; ++i) {
    const unsigned bit = s[i].start_bit - kFaultFirstBit;
    put_flag(f, s[i], (m.faults >> bit) & 1u);
  }
  put_count(f, s[kDroppedFrames], m.dropped_frames);
  put_count(f, s[kRingOverruns], m.ring_overruns);
  put_count(f, s[kCanSendErrors], m.can_send_errors);
  put_count(f, s[kMethod], m.method);
  e2e_protect(f, counter);
  return f;
}

CanFrame encode_timing(const TimingMsg& m, const MessageIds& ids, std::uint8_t counter) noexcept {
  using namespace sig_timing;
  const auto& s = kTimingSignals;
  CanFrame f = blank_frame(ids, MessageKind::Timing);
  put_count(f, s[kExposure], m.exposure_us);
  put_count(f, s[kProcessingTime], m.processing_time_us);
  put_count(f, s[kLateWakeups], m.late_wakeups);
  e2e_protect(f, counter);
  return f;
}

CanFrame encode_ride_height(const RideHeightMsg& m, const MessageIds& ids, std::uint8_t counter) noexcept {
  using namespace sig_ride_height;
  const auto& s = kRideHeightSignals;
  CanFrame f = blank_frame(ids, MessageKind::RideHeight);
  put_flag(f, s[kHeightValid], m.height_valid);
  put_flag(f, s[kPitchValid], m.pitch_valid);
  put_flag(f, s[kRollValid], m.roll_valid);
  put_count(f, s[kScaleSource], static_cast<std::uint8_t>(m.scale_source));
  put(f, s[kHeight], m.height_valid ? m.height_mm : 0.0);
  put(f, s[kPitch], m.pitch_valid ? m.pitch_deg : 0.0);
  put(f, s[kRoll], m.roll_valid ? m.roll_deg : 0.0);
  put_count(f, s[kHeightAge], m.age_ms);
  e2e_protect(f, counter);
  return f;
}

RideHeightMsg ride_height_from_estimate(const BusEstimate* e, std::int64_t now_ns, const ValidityRule& rule) noexcept {
  RideHeightMsg m;
  if (e == nullptr) return m;
  m.scale_source = e->scale_source;
  if (!e->has_height && !e->has_pitch && !e->has_roll) return m;  // age stays 127: nothing measured
  const std::int64_t age_ms = (now_ns - e->t_ns) / 1'000'000;
  m.age_ms = static_cast<std::uint32_t>(std::clamp<std::int64_t>(age_ms, 0, 127));
  if (std::llabs(age_ms) > rule.stale_after_ms) return m;
  using namespace sig_ride_height;
  const auto& s = kRideHeightSignals;
  m.height_valid = e->has_height && in_range(s[kHeight], e->height_mm);
  m.pitch_valid = e->has_pitch && in_range(s[kPitch], e->pitch_deg);
  m.roll_valid = e->has_roll && in_range(s[kRoll], e->roll_deg);
  if (m.height_valid) m.height_mm = e->height_mm;
  if (m.pitch_valid) m.pitch_deg = e->pitch_deg;
  if (m.roll_valid) m.roll_deg = e->roll_deg;
  return m;
}

VelocityPair velocity_from_estimate(const BusEstimate* e, std::int64_t now_ns, const ValidityRule& rule,
                                    bool plausible) noexcept {
  VelocityPair out;
  if (e == nullptr) return out;  // all invalid, age 65535
  out.xy.scale_source = e->scale_source;

  const std::int64_t age_ns = now_ns - e->t_ns;
  const std::int64_t age_ms = age_ns / 1'000'000;
  out.fresh = std::llabs(age_ms) <= rule.stale_after_ms;
  out.xy.age_ms = static_cast<std::uint32_t>(std::clamp<std::int64_t>(age_ms, 0, 65535));
  VelocityMsg& v = out.velocity;
  // The receiver sees the quality even when it made the values invalid.
  v.quality_pct = std::isfinite(e->quality) ? std::clamp(e->quality, 0.0, 1.0) * 100.0 : 0.0;
  if (!out.fresh || !quality_passes(e->quality, rule.min_quality) || !plausible) return out;

  using namespace sig_velocity;
  const auto& s = kVelocitySignals;
  v.speed_valid = e->has_speed && in_range(s[kSpeed], e->speed_mps);
  v.direction_valid = e->has_direction && in_range(s[kDirection], e->direction_deg);
  v.yaw_rate_valid = e->has_yaw_rate && in_range(s[kYawRate], e->yaw_rate_dps);
  v.valid = v.speed_valid && v.direction_valid;
  if (v.speed_valid) v.speed_mps = e->speed_mps;
  if (v.direction_valid) v.direction_deg = e->direction_deg;
  if (v.yaw_rate_valid) v.yaw_rate_dps = e->yaw_rate_dps;

  const auto& sx = kVelocityXySignals;
  out.xy.valid = e->has_velocity_xy && in_range(sx[sig_velocity_xy::kVx], e->vx_mps) &&
                 in_range(sx[sig_velocity_xy::kVy], e->vy_mps);
  if (out.xy.valid) {
    out.xy.vx_mps = e->vx_mps;
    out.xy.vy_mps = e->vy_mps;
  }
  return out;
}

Encoder::Encoder(const EncoderConfig& config) : config_(config), ids_{config.base_id} {
  validate_base_id(config.base_id);
}

std::uint8_t Encoder::next_counter(MessageKind kind) noexcept {
  std::uint8_t& c = counters_[static_cast<std::size_t>(kind)];
  const std::uint8_t now = c;
  c = static_cast<std::uint8_t>((c + 1u) & 0x0Fu);
  return now;
}

CanFrame Encoder::velocity(const VelocityMsg& m) noexcept {
  return encode_velocity(m, ids_, next_counter(MessageKind::Velocity));
}
CanFrame Encoder::velocity_xy(const VelocityXyMsg& m) noexcept {
  return encode_velocity_xy(m, ids_, next_counter(MessageKind::VelocityXy));
}
CanFrame Encoder::status(const StatusMsg& m) noexcept {
  return encode_status(m, ids_, next_counter(MessageKind::Status));
}
CanFrame Encoder::timing(const TimingMsg& m) noexcept {
  return encode_timing(m, ids_, next_counter(MessageKind::Timing));
}
CanFrame Encoder::ride_height(const RideHeightMsg& m) noexcept {
  return encode_ride_height(m, ids_, next_counter(MessageKind::RideHeight));
}

VelocityPair Encoder::estimate_frames(const BusEstimate* estimate, std::int64_t now_ns, const ValidityRule& rule,
                                      bool plausible, CanFrame& velocity_out, CanFrame& xy_out) noexcept {
  const VelocityPair p = velocity_from_estimate(estimate, now_ns, rule, plausible);
  velocity_out = velocity(p.velocity);
  xy_out = velocity_xy(p.xy);
  return p;
}

DecodedFrame decode(const CanFrame& frame, const MessageIds& ids) noexcept {
  DecodedFrame d;
  if (frame.extended || frame.remote || frame.error) return d;
  const std::optional<MessageKind> kind = ids.kind_of(frame.id);
  if (!kind) return d;
  d.kind = *kind;
  if (frame.len != 8) {
    d.status = DecodeStatus::BadLength;
    return d;
  }
  d.status = e2e_crc_ok(frame) ? DecodeStatus::Ok : DecodeStatus::BadCrc;
  d.counter = e2e_counter(frame);
  switch (*kind) {
    case MessageKind::Velocity: {
      using namespace sig_velocity;
      const auto& s = kVelocitySignals;
      d.velocity.valid = get_flag(frame, s[kValid]);
      d.velocity.speed_valid = get_flag(frame, s[kSpeedValid]);
      d.velocity.direction_valid = get_flag(frame, s[kDirectionValid]);
      d.velocity.yaw_rate_valid = get_flag(frame, s[kYawRateValid]);
      d.velocity.speed_mps = get(frame, s[kSpeed]);
      d.velocity.direction_deg = get(frame, s[kDirection]);
      d.velocity.yaw_rate_dps = get(frame, s[kYawRate]);
      d.velocity.quality_pct = get(frame, s[kQuality]);
      break;
    }
    case MessageKind::VelocityXy: {
      using namespace sig_velocity_xy;
      const auto& s = kVelocityXySignals;
      d.xy.valid = get_flag(frame, s[kValid]);
      d.xy.scale_source = static_cast<ScaleSourceCode>(get_uint<std::uint8_t>(frame, s[kScaleSource]));
      d.xy.vx_mps = get(frame, s[kVx]);
      d.xy.vy_mps = get(frame, s[kVy]);
      d.xy.age_ms = get_uint<std::uint32_t>(frame, s[kAge]);
      break;
    }
    case MessageKind::Status: {
      using namespace sig_status;
      const auto& s = kStatusSignals;
      d.status_msg.state = static_cast<SensorState>(get_uint<std::uint8_t>(frame, s[kState]));
      std::uint16_t faults = 0;
      for (std::size_t i = kFirstFault; i < kFirstFault + kFaultCount; ++i) {
        if (get_flag(frame, s[i])) faults = static_cast<std::uint16_t>(faults | (1u << (s[i].start_bit - kFaultFirstBit)));
      }
      d.status_msg.faults = faults;
      d.status_msg.dropped_frames = get_uint<std::uint8_t>(frame, s[kDroppedFrames]);
      d.status_msg.ring_overruns = get_uint<std::uint8_t>(frame, s[kRingOverruns]);
      d.status_msg.can_send_errors = get_uint<std::uint8_t>(frame, s[kCanSendErrors]);
      d.status_msg.method = get_uint<std::uint8_t>(frame, s[kMethod]);
      break;
    }
    case MessageKind::Timing: {
      using namespace sig_timing;
      const auto& s = kTimingSignals;
      d.timing.exposure_us = get_uint<std::uint32_t>(frame, s[kExposure]);
      d.timing.processing_time_us = get_uint<std::uint32_t>(frame, s[kProcessingTime]);
      d.timing.late_wakeups = get_uint<std::uint8_t>(frame, s[kLateWakeups]);
      break;
    }
    case MessageKind::RideHeight: {
      using namespace sig_ride_height;
      const auto& s = kRideHeightSignals;
      d.ride.height_valid = get_flag(frame, s[kHeightValid]);
      d.ride.pitch_valid = get_flag(frame, s[kPitchValid]);
      d.ride.roll_valid = get_flag(frame, s[kRollValid]);
      d.ride.scale_source = static_cast<ScaleSourceCode>(get_uint<std::uint8_t>(frame, s[kScaleSource]));
      d.ride.height_mm = get(frame, s[kHeight]);
      d.ride.pitch_deg = get(frame, s[kPitch]);
      d.ride.roll_deg = get(frame, s[kRoll]);
      d.ride.age_ms = get_uint<std::uint32_t>(frame, s[kHeightAge]);
      break;
    }
  }
  return d;
}

}  // namespace gvs::can
