#include "gvs/daemon/health.hpp"

#include <fmt/format.h>

namespace gvs::daemon {

namespace {

std::string estimate_text(const PublishedEstimate& latest, std::int64_t now_ns) {
  if (latest.sequence == 0) return "no estimate yet";
  const core::VelocityEstimate& e = latest.estimate;
  const double age_ms = static_cast<double>(now_ns - e.t_ns) / 1e6;
  if (!e.has_speed) return fmt::format("no speed ({}), age {:.0f} ms", core::method_word(e.method), age_ms);
  return fmt::format("{:.2f} m/s, direction {}, yaw {}, quality {:.2f}, {}{}, age {:.0f} ms", e.speed_mps,
                     e.has_direction ? fmt::format("{:+.2f} deg", e.direction_deg) : std::string("-"),
                     e.has_yaw_rate ? fmt::format("{:+.1f} deg/s", e.yaw_rate_dps) : std::string("-"), e.quality,
                     core::method_word(e.method), latest.plausible ? "" : ", implausible (held back)", age_ms);
}

/// The rejected frames per reason that occurred, e.g. " [unreadable 2 (+1), wrong-size 1 (+0)]".
std::string reject_text(const HealthSnapshot& n, const HealthSnapshot& p) {
  std::string out;
  for (const core::RejectReasonInfo& r : core::kRejectReasons) {
    const auto i = static_cast<std::size_t>(r.reason);
    if (n.frames_rejected_by[i] == 0) continue;
    out += fmt::format("{}{} {} (+{})", out.empty() ? " [" : ", ", core::reject_word(r.reason), n.frames_rejected_by[i],
                       n.frames_rejected_by[i] - p.frames_rejected_by[i]);
  }
  if (!out.empty()) out += ']';
  return out;
}

struct GroupInfo {
  HealthGroup group;
  const char* prefix;
  bool only_when_nonzero;  ///< the light and height parts appear only with a [light] driver or a CAN height
};

constexpr GroupInfo kGroups[] = {
    {HealthGroup::capture, "capture ", false},  {HealthGroup::processing, "processing ", false},
    {HealthGroup::can, "CAN ", false},          {HealthGroup::exposure, "", false},
    {HealthGroup::light, "light ", true},      {HealthGroup::height, "height ", true},
};

/// One group of the line from the declared counters ("" when it is not shown).
std::string group_text(const GroupInfo& g, const HealthSnapshot& n, const HealthSnapshot& p, double interval_s) {
  std::string items;
  bool any_nonzero = false;
  for (const HealthField& f : kHealthFields) {
    if (f.group != g.group || f.show == HealthShow::hidden) continue;
    const std::int64_t v = f.value(n);
    const std::int64_t d = v - f.value(p);
    any_nonzero = any_nonzero || v != 0;
    if (f.show == HealthShow::nonzero && v == 0) continue;
    const double rate = interval_s > 0.0 ? static_cast<double>(d) / interval_s : 0.0;
    std::string item = fmt::format(fmt::runtime(f.text), fmt::arg("v", v), fmt::arg("rate", rate),
                                   fmt::arg("ms", static_cast<double>(v) / 1e6));
    if (f.show == HealthShow::delta || f.show == HealthShow::delta_by_reason) item += fmt::format(" (+{})", d);
    if (f.show == HealthShow::delta_by_reason) item += reject_text(n, p);
    items += (items.empty() ? "" : ", ") + item;
  }
  if (g.only_when_nonzero && !any_nonzero) return {};
  return g.prefix + items;
}

}  // namespace

std::string format_health_line(const HealthSnapshot& n, const HealthSnapshot& p, const PublishedEstimate& latest,
                               std::int64_t now_ns, double interval_s) {
  std::string line = "health: ";
  bool first = true;
  for (const GroupInfo& g : kGroups) {
    const std::string part = group_text(g, n, p, interval_s);
    if (part.empty()) continue;
    line += (first ? "" : " | ") + part;
    first = false;
  }
  return line + " | latest: " + estimate_text(latest, now_ns);
}

std::string format_status_text(const HealthSnapshot& n, const PublishedEstimate& latest, std::int64_t now_ns) {
  return fmt::format("{}; {} frames, {} overruns, {} send errors, {} late wake-ups", estimate_text(latest, now_ns),
                     n.frames_captured, n.ring_overruns, n.send_errors, n.late_wakeups);
}

}  // namespace gvs::daemon
