// Helpers for the gvsd tests: read a candump log back into decoded gvs
// messages, and simple statistics.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <string>
#include <vector>

#include "gvs/can/candump.hpp"
#include "gvs/can/codec.hpp"

namespace gvs::daemon::testing {

struct LoggedMessage {
  std::int64_t t_ns = 0;
  can::DecodedFrame decoded;
};

struct CandumpLog {
  std::vector<LoggedMessage> velocity, velocity_xy, status, timing, ride_height;
  std::size_t lines = 0;
  std::size_t unparsed = 0;
  std::size_t bad_crc = 0;
};

inline CandumpLog read_candump_log(const std::string& path, std::uint32_t base_id = can::kDefaultBaseId) {
  CandumpLog log;
  std::ifstream in(path);
  std::string line;
  can::MessageIds ids;
  ids.base = base_id;
  while (std::getline(in, line)) {
    ++log.lines;
    const auto parsed = can::parse_candump_line(line);
    if (!parsed) {
      ++log.unparsed;
      continue;
    }
    LoggedMessage m{parsed->t_ns, can::decode(parsed->frame, ids)};
    if (m.decoded.status == can::DecodeStatus::BadCrc) ++log.bad_crc;
    if (m.decoded.status != can::DecodeStatus::Ok) continue;
    switch (m.decoded.kind) {
      case can::MessageKind::Velocity: log.velocity.push_back(m); break;
      case can::MessageKind::VelocityXy: log.velocity_xy.push_back(m); break;
      case can::MessageKind::Status: log.status.push_back(m); break;
      case can::MessageKind::Timing: log.timing.push_back(m); break;
      case can::MessageKind::RideHeight: log.ride_height.push_back(m); break;
    }
  }
  return log;
}

/// Intervals between consecutive messages, in ms.
inline std::vector<double> periods_ms(const std::vector<LoggedMessage>& msgs) {
  std::vector<double> p;
  for (std::size_t i = 1; i < msgs.size(); ++i) p.push_back(static_cast<double>(msgs[i].t_ns - msgs[i - 1].t_ns) / 1e6);
  return p;
}

/// The q-quantile (0..1) by nearest rank.
inline double quantile(std::vector<double> v, double q) {
  if (v.empty()) return NAN;
  std::sort(v.begin(), v.end());
  const auto i = static_cast<std::size_t>(std::clamp(q, 0.0, 1.0) * static_cast<double>(v.size() - 1) + 0.5);
  return v[std::min(i, v.size() - 1)];
}

/// How an absolute schedule of period `period_ms` held over a log: its
/// messages' offsets from the grid t_0 + k * period, compared by median over
/// the first and the last `window` messages. Scheduling lateness moves single
/// messages and leaves both medians alone; a schedule that drifts or bursts
/// moves the median by a fraction of a period; a skipped period (a stall
/// longer than a period, which gvsd skips and flags) moves it by one period.
struct ScheduleHold {
  double phase_step_ms = 0.0;  ///< median offset at the end minus at the start
  long whole_periods = 0;      ///< phase_step_ms in whole periods (skipped ones)
  double off_grid_ms = 0.0;    ///< phase_step_ms minus whole_periods * period
};

inline ScheduleHold schedule_hold(const std::vector<LoggedMessage>& msgs, double period_ms, std::size_t window = 50) {
  ScheduleHold h;
  if (msgs.size() < 2 * window) return h;
  std::vector<double> first, last;
  for (std::size_t k = 0; k < msgs.size(); ++k) {
    const double offset_ms = static_cast<double>(msgs[k].t_ns - msgs[0].t_ns) / 1e6 - static_cast<double>(k) * period_ms;
    if (k < window) first.push_back(offset_ms);
    if (k >= msgs.size() - window) last.push_back(offset_ms);
  }
  h.phase_step_ms = quantile(last, 0.5) - quantile(first, 0.5);
  h.whole_periods = std::lround(h.phase_step_ms / period_ms);
  h.off_grid_ms = h.phase_step_ms - static_cast<double>(h.whole_periods) * period_ms;
  return h;
}

}  // namespace gvs::daemon::testing
