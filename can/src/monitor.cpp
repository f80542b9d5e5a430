#include "gvs/can/monitor.hpp"

#include <cinttypes>
#include <cstdarg>
#include <cstdio>
#include <string>
#include <string_view>

#include "gvs/can/bus_health.hpp"
#include "gvs/can/e2e.hpp"

namespace gvs::can {

namespace {

/// a - b in milliseconds, without integer overflow for arbitrary inputs.
double diff_ms(std::int64_t a, std::int64_t b) noexcept {
  return (static_cast<double>(a) - static_cast<double>(b)) / 1e6;
}

void appendf(std::string& out, const char* fmt, ...) __attribute__((format(printf, 2, 3)));
void appendf(std::string& out, const char* fmt, ...) {
  char buf[512];
  va_list args;
  va_start(args, fmt);
  const int n = std::vsnprintf(buf, sizeof buf, fmt, args);
  va_end(args);
  if (n > 0) out.append(buf, static_cast<std::size_t>(n) < sizeof buf ? static_cast<std::size_t>(n) : sizeof buf - 1);
}

const char* yes_no(bool v) { return v ? "yes" : "NO "; }

const char* scale_source_word(ScaleSourceCode c) {
  switch (c) {
    case ScaleSourceCode::Nominal: return "nominal height (uncorrected)";
    case ScaleSourceCode::LaserDots: return "laser dots";
    case ScaleSourceCode::External: return "external height";
  }
  return "?";
}

/// " (Camera, Implausible)": the set fault bits by their DBC names without
/// the GVS_Fault prefix; empty when none is set.
std::string fault_names(std::uint16_t faults) {
  std::string out;
  for (std::size_t i = sig_status::kFirstFault; i < sig_status::kFirstFault + sig_status::kFaultCount; ++i) {
    const SignalSpec& sig = kStatusSignals[i];
    const unsigned bit = static_cast<unsigned>(sig.start_bit - kFaultFirstBit);
    if (((static_cast<unsigned>(faults) >> bit) & 1u) == 0) continue;
    out += out.empty() ? " (" : ", ";
    out += sig.name.substr(std::string_view("GVS_Fault").size());
  }
  if (!out.empty()) out += ')';
  return out;
}

}  // namespace

double MessageStats::recent_rate_hz() const noexcept {
  if (recent_count < 2) return 0.0;
  const std::size_t newest = (recent_next + kWindow - 1) % kWindow;
  const std::size_t oldest = recent_count < kWindow ? 0 : recent_next;
  const double span_ms = diff_ms(recent_t_ns[newest], recent_t_ns[oldest]);
  if (!(span_ms > 0.0)) return 0.0;
  return static_cast<double>(recent_count - 1) * 1000.0 / span_ms;
}

double MessageStats::mean_rate_hz() const noexcept {
  if (frames < 2) return 0.0;
  const double span_ms = diff_ms(last_t_ns, first_t_ns);
  if (!(span_ms > 0.0)) return 0.0;
  return static_cast<double>(frames - 1) * 1000.0 / span_ms;
}

void MonitorState::feed(const CanFrame& frame, std::int64_t t_ns) noexcept {
  ++total_frames_;
  last_t_ns_ = t_ns;
  if (frame.error) {
    const ErrorFrameInfo e = decode_error_frame(frame);
    ++bus_errors_.error_frames;
    if (e.bus_off) ++bus_errors_.bus_off;
    if (e.error_passive) ++bus_errors_.error_passive;
    if (e.error_warning || e.overflow || e.tx_timeout) ++bus_errors_.controller_problems;
    if (e.restarted) ++bus_errors_.restarts;
    return;
  }
  const DecodedFrame d = decode(frame, ids_);
  if (d.status == DecodeStatus::NotOurs) {
    ++other_frames_;
    return;
  }
  const auto k = static_cast<std::size_t>(d.kind);
  MessageStats& s = stats_[k];
  if (s.frames == 0) s.first_t_ns = t_ns;
  if (s.frames > 0) {
    const double gap = diff_ms(t_ns, s.last_t_ns);
    if (gap > s.max_gap_ms) s.max_gap_ms = gap;
  }
  ++s.frames;
  s.last_t_ns = t_ns;
  s.recent_t_ns[s.recent_next] = t_ns;
  s.recent_next = (s.recent_next + 1) % MessageStats::kWindow;
  if (s.recent_count < MessageStats::kWindow) ++s.recent_count;

  if (d.status == DecodeStatus::BadLength) {
    ++s.bad_length;
    return;
  }
  if (d.status == DecodeStatus::BadCrc) {
    ++s.crc_errors;
    return;
  }
  if (s.have_counter) {
    const std::uint8_t delta = e2e_counter_delta(s.last_counter, d.counter);
    if (delta == 0) {
      ++s.counter_repeats;
      ++s.counter_jumps;
    } else if (delta != 1) {
      ++s.counter_jumps;
      s.frames_lost += delta - 1u;
    }
  }
  s.have_counter = true;
  s.last_counter = d.counter;
  has_[k] = true;
  switch (d.kind) {
    case MessageKind::Velocity: velocity_ = d.velocity; break;
    case MessageKind::VelocityXy: xy_ = d.xy; break;
    case MessageKind::Status: status_ = d.status_msg; break;
    case MessageKind::Timing: timing_ = d.timing; break;
    case MessageKind::RideHeight: ride_ = d.ride; break;
  }
}

bool MonitorState::silent(MessageKind kind, std::int64_t now_ns) const noexcept {
  const MessageStats& s = stats(kind);
  if (s.frames == 0) return false;
  const double mean_hz = s.mean_rate_hz();
  const double expected_gap_ms = mean_hz > 0.0 ? 3.0 * 1000.0 / mean_hz : 0.0;
  return diff_ms(now_ns, s.last_t_ns) > (expected_gap_ms > kSilentAfterMs ? expected_gap_ms : kSilentAfterMs);
}

std::string MonitorState::render(std::int64_t now_ns) const {
  std::string out;
  out.reserve(2048);
  appendf(out, "gvs monitor  base ID 0x%03" PRIX32 "   frames %" PRIu64 "  (other IDs %" PRIu64 ")\n", ids_.base,
          total_frames_, other_frames_);
  const double quiet_ms = total_frames_ > 0 ? diff_ms(now_ns, last_t_ns_) : 0.0;
  if (quiet_ms > kSilentAfterMs) {
    appendf(out, "NO DATA for %.0f ms: the values below are the last received, not current\n", quiet_ms);
  }
  if (has(MessageKind::Velocity)) {
    // A silent sender's last "valid" is history: shown as "old", never "yes".
    const bool stale = silent(MessageKind::Velocity, now_ns);
    const auto validity = [stale](bool v) { return stale ? "old" : yes_no(v); };
    const VelocityMsg& v = velocity_;
    appendf(out, "speed      %8.2f m/s  %7.2f km/h  valid %s\n", v.speed_mps, v.speed_mps * 3.6,
            validity(v.speed_valid));
    appendf(out, "direction  %8.2f deg                valid %s\n", v.direction_deg, validity(v.direction_valid));
    appendf(out, "yaw rate   %8.1f deg/s              valid %s\n", v.yaw_rate_dps, validity(v.yaw_rate_valid));
    appendf(out, "GVS_Valid  %s   quality %3.0f %%\n", stale ? "- (old)" : v.valid ? "1" : "0", v.quality_pct);
  } else {
    out += "speed/direction/yaw rate: no GVS_Velocity received\n";
  }
  if (has(MessageKind::VelocityXy)) {
    appendf(out, "vx %8.3f m/s  vy %8.3f m/s  valid %s  age %" PRIu32 " ms%s\n", xy_.vx_mps, xy_.vy_mps,
            silent(MessageKind::VelocityXy, now_ns) ? "old" : yes_no(xy_.valid), xy_.age_ms,
            xy_.age_ms == 65535 ? " (none)" : "");
  } else {
    out += "vx/vy: no GVS_VelocityXY received\n";
  }
  if (has(MessageKind::RideHeight)) {
    const bool stale = silent(MessageKind::RideHeight, now_ns);
    const auto validity = [stale](bool v) { return stale ? "old" : yes_no(v); };
    appendf(out,
            "height %7.2f mm  valid %s  pitch %6.2f deg  valid %s  roll %6.2f deg  valid %s  age %" PRIu32
            " ms  scale: %s\n",
            ride_.height_mm, validity(ride_.height_valid), ride_.pitch_deg, validity(ride_.pitch_valid),
            ride_.roll_deg, validity(ride_.roll_valid), ride_.age_ms, scale_source_word(ride_.scale_source));
  }
  if (has(MessageKind::Status)) {
    const char* word = method_word_ != nullptr ? method_word_(status_.method) : nullptr;
    appendf(out, "state %-9s faults 0x%04X%s  dropped %u  overruns %u  CAN send errors %u  method %u (%s)\n",
            std::string(state_name(static_cast<std::uint8_t>(status_.state))).c_str(), status_.faults,
            fault_names(status_.faults).c_str(), status_.dropped_frames, status_.ring_overruns,
            status_.can_send_errors, status_.method, word != nullptr ? word : "?");
  }
  if (has(MessageKind::Timing)) {
    appendf(out, "exposure %" PRIu32 " us  processing %" PRIu32 " us  late wake-ups %u\n", timing_.exposure_us,
            timing_.processing_time_us, timing_.late_wakeups);
  }
  out += "message          frames   rate Hz  mean Hz  max gap ms  since ms  CRC err  bad len  cnt jumps  lost\n";
  for (const MessageSpec& m : kMessages) {
    const MessageStats& s = stats(m.kind);
    const double since = s.frames > 0 ? diff_ms(now_ns, s.last_t_ns) : 0.0;
    appendf(out, "%-15.*s %7" PRIu64 "  %8.1f %8.1f %11.1f %9.0f %8" PRIu64 " %8" PRIu64 " %10" PRIu64 " %5" PRIu64 "\n",
            static_cast<int>(m.name.size()), m.name.data(), s.frames,
            silent(m.kind, now_ns) ? 0.0 : s.recent_rate_hz(), s.mean_rate_hz(),
            s.max_gap_ms, since, s.crc_errors, s.bad_length, s.counter_jumps, s.frames_lost);
  }
  appendf(out, "bus error frames %" PRIu64 "  bus-off %" PRIu64 "  error-passive %" PRIu64
               "  controller %" PRIu64 "  restarts %" PRIu64 "  malformed log lines %" PRIu64 "\n",
          bus_errors_.error_frames, bus_errors_.bus_off, bus_errors_.error_passive,
          bus_errors_.controller_problems, bus_errors_.restarts, malformed_lines_);
  return out;
}

}  // namespace gvs::can
