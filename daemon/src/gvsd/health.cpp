#include "gvs/daemon/health.hpp"

#include <fmt/format.h>

namespace gvs::daemon {

namespace {

std::string estimate_text(const PublishedEstimate& latest, std::int64_t now_ns) {
  if (latest.sequence == 0) return "no estimate yet";
  const dsp::VelocityEstimate& e = latest.estimate;
  const double age_ms = static_cast<double>(now_ns - e.t_ns) / 1e6;
  if (!e.has_speed) return fmt::format("no speed ({}), age {:.0f} ms", dsp::method_word(e.method), age_ms);
  return fmt::format("{:.2f} m/s, direction {}, yaw {}, quality {:.2f}, {}{}, age {:.0f} ms", e.speed_mps,
                     e.has_direction ? fmt::format("{:+.2f} deg", e.direction_deg) : std::string("-"),
                     e.has_yaw_rate ? fmt::format("{:+.1f} deg/s", e.yaw_rate_dps) : std::string("-"), e.quality,
                     dsp::method_word(e.method), latest.plausible ? "" : ", implausible (held back)", age_ms);
}

/// The rejected frames per reason that occurred, e.g. " [unreadable 2 (+1), wrong-size 1 (+0)]".
std::string reject_text(const HealthSnapshot& n, const HealthSnapshot& p) {
  std::string out;
  for (const RejectReasonInfo& r : kRejectReasons) {
    const auto i = static_cast<std::size_t>(r.reason);
    if (n.frames_rejected_by[i] == 0) continue;
    out += fmt::format("{}{} {} (+{})", out.empty() ? " [" : ", ", reject_word(r.reason), n.frames_rejected_by[i],
                       n.frames_rejected_by[i] - p.frames_rejected_by[i]);
  }
  if (!out.empty()) out += ']';
  return out;
}

/// The [light] part; empty when no light driver ran.
std::string light_text(const HealthSnapshot& n, const HealthSnapshot& p) {
  if (n.light_plans == 0 && n.light_errors == 0) return {};
  return fmt::format(" | light {} plans, {} edges, late edges {} (+{}), errors {} (+{}), max lateness {:.3f} ms",
                     n.light_plans, n.light_edges, n.light_late_edges, n.light_late_edges - p.light_late_edges,
                     n.light_errors, n.light_errors - p.light_errors,
                     static_cast<double>(n.light_late_max_ns) / 1e6);
}

}  // namespace

std::string format_health_line(const HealthSnapshot& n, const HealthSnapshot& p, const PublishedEstimate& latest,
                               std::int64_t now_ns, double interval_s) {
  const double fps = interval_s > 0.0 ? static_cast<double>(n.frames_captured - p.frames_captured) / interval_s : 0.0;
  return fmt::format(
      "health: capture {} frames ({:.1f} fps), ring overruns {} (+{}), dropped {} (+{}), source errors {} (+{}), "
      "late {} | processing {} frames, skipped {} (+{}), rejected {} (+{}){}, estimator failures {} (+{}), "
      "implausible {} (+{}), max {:.2f} ms | "
      "CAN {} frames sent, {} flagged invalid (+{}), send errors {} (+{}{}), late wake-ups {} (+{}), "
      "missed periods {}, max lateness {:.3f} ms | exposure updates {}{} | latest: {}",
      n.frames_captured, fps, n.ring_overruns, n.ring_overruns - p.ring_overruns, n.frames_dropped,
      n.frames_dropped - p.frames_dropped, n.source_errors, n.source_errors - p.source_errors, n.capture_late,
      n.frames_processed, n.frames_skipped, n.frames_skipped - p.frames_skipped, n.frames_rejected,
      n.frames_rejected - p.frames_rejected, reject_text(n, p), n.estimator_failures,
      n.estimator_failures - p.estimator_failures, n.implausible_estimates,
      n.implausible_estimates - p.implausible_estimates, static_cast<double>(n.processing_max_ns) / 1e6, n.frames_sent,
      n.invalid_sent, n.invalid_sent - p.invalid_sent, n.send_errors, n.send_errors - p.send_errors,
      n.last_send_errno != 0 ? fmt::format(", last errno {}", n.last_send_errno) : std::string(),
      n.late_wakeups, n.late_wakeups - p.late_wakeups, n.missed_ticks,
      static_cast<double>(n.wakeup_late_max_ns) / 1e6, n.exposure_updates, light_text(n, p),
      estimate_text(latest, now_ns));
}

std::string format_status_text(const HealthSnapshot& n, const PublishedEstimate& latest, std::int64_t now_ns) {
  return fmt::format("{}; {} frames, {} overruns, {} send errors, {} late wake-ups", estimate_text(latest, now_ns),
                     n.frames_captured, n.ring_overruns, n.send_errors, n.late_wakeups);
}

}  // namespace gvs::daemon
