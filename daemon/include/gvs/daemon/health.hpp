// The periodic health line: what the real-time threads counted.
#pragma once

#include <cstdint>
#include <string>

#include "gvs/daemon/health_counters.hpp"
#include "gvs/daemon/published_estimate.hpp"

namespace gvs::daemon {

/// One line: totals with the change since `previous`, the latest estimate
/// and its age at `now_ns`.
std::string format_health_line(const HealthSnapshot& now, const HealthSnapshot& previous,
                               const PublishedEstimate& latest, std::int64_t now_ns, double interval_s);

/// Short text for sd_notify STATUS=.
std::string format_status_text(const HealthSnapshot& now, const PublishedEstimate& latest, std::int64_t now_ns);

}  // namespace gvs::daemon
