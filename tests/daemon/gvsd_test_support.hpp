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

}  // namespace gvs::daemon::testing
