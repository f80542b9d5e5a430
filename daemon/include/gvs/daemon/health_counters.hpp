// Counters the real-time threads bump instead of logging. Each counter has
// exactly one writing thread; the main thread reads them for the health line
// and the sender copies them into the status message.
#pragma once

#include <array>
#include <atomic>
#include <cstdint>

#include "gvs/daemon/reject_reason.hpp"

namespace gvs::daemon {

/// Increments a single-writer counter (no read-modify-write bus lock needed).
inline void bump(std::atomic<std::uint64_t>& c, std::uint64_t by = 1) noexcept {
  c.store(c.load(std::memory_order_relaxed) + by, std::memory_order_relaxed);
}
/// Raises a single-writer maximum.
inline void raise_max(std::atomic<std::int64_t>& m, std::int64_t v) noexcept {
  if (v > m.load(std::memory_order_relaxed)) m.store(v, std::memory_order_relaxed);
}

struct HealthCounters {
  // capture thread
  std::atomic<std::uint64_t> frames_captured{0};
  std::atomic<std::uint64_t> ring_overruns{0};     ///< frames lost because every slot was busy
  std::atomic<std::uint64_t> frames_dropped{0};    ///< gaps in the source's frame index
  std::atomic<std::uint64_t> source_errors{0};
  std::atomic<std::uint64_t> capture_late{0};      ///< frames delivered more than a period late
  std::atomic<std::uint64_t> exposure_updates{0};
  std::atomic<std::uint64_t> capture_heartbeat{0};
  // capture thread: LED ring and trigger ([light])
  std::atomic<std::uint64_t> light_plans{0};       ///< frames whose exposure plan was fired
  std::atomic<std::uint64_t> light_edges{0};       ///< output edges driven
  std::atomic<std::uint64_t> light_late_edges{0};  ///< edges later than [light] late_limit_us
  std::atomic<std::uint64_t> light_errors{0};      ///< failed set-value / sysfs writes, plans the driver refused
  std::atomic<std::int64_t> light_late_max_ns{0};
  // processing thread
  std::atomic<std::uint64_t> frames_processed{0};
  std::atomic<std::uint64_t> frames_skipped{0};    ///< older frames passed over for the newest
  std::atomic<std::uint64_t> estimator_failures{0};///< frames without a speed estimate
  std::atomic<std::uint64_t> frames_rejected{0};   ///< bad input frames (unreadable, wrong size or exposure, time backwards)
  std::array<std::atomic<std::uint64_t>, kRejectReasonCount> frames_rejected_by{};  ///< the same, per RejectReason
  std::atomic<std::uint64_t> implausible_estimates{0};///< held back by the plausibility gate
  std::atomic<std::int64_t> processing_max_ns{0};
  std::atomic<std::uint64_t> processing_heartbeat{0};
  // sender thread
  std::atomic<std::uint64_t> sender_ticks{0};
  std::atomic<std::uint64_t> late_wakeups{0};      ///< woke later than the configured tolerance
  std::atomic<std::uint64_t> missed_ticks{0};      ///< whole periods skipped
  std::atomic<std::uint64_t> send_errors{0};
  std::atomic<std::uint64_t> frames_sent{0};
  std::atomic<std::uint64_t> invalid_sent{0};      ///< velocity messages flagged invalid (stale, no estimate, low quality, implausible)
  std::atomic<std::int64_t> wakeup_late_max_ns{0};
  std::atomic<int> last_send_errno{0};
  std::atomic<std::uint64_t> sender_heartbeat{0};
};

/// A plain copy of the counters at one moment.
struct HealthSnapshot {
  std::uint64_t frames_captured = 0, ring_overruns = 0, frames_dropped = 0, source_errors = 0,
                capture_late = 0, exposure_updates = 0;
  std::uint64_t light_plans = 0, light_edges = 0, light_late_edges = 0, light_errors = 0;
  std::int64_t light_late_max_ns = 0;
  std::uint64_t frames_processed = 0, frames_skipped = 0, estimator_failures = 0, frames_rejected = 0,
                implausible_estimates = 0;
  RejectCounts frames_rejected_by{};
  std::int64_t processing_max_ns = 0;
  std::uint64_t sender_ticks = 0, late_wakeups = 0, missed_ticks = 0, send_errors = 0,
                frames_sent = 0, invalid_sent = 0;
  std::int64_t wakeup_late_max_ns = 0;
  int last_send_errno = 0;
};

inline HealthSnapshot snapshot(const HealthCounters& c) noexcept {
  constexpr auto r = std::memory_order_relaxed;
  HealthSnapshot s;
  s.frames_captured = c.frames_captured.load(r);
  s.ring_overruns = c.ring_overruns.load(r);
  s.frames_dropped = c.frames_dropped.load(r);
  s.source_errors = c.source_errors.load(r);
  s.capture_late = c.capture_late.load(r);
  s.exposure_updates = c.exposure_updates.load(r);
  s.light_plans = c.light_plans.load(r);
  s.light_edges = c.light_edges.load(r);
  s.light_late_edges = c.light_late_edges.load(r);
  s.light_errors = c.light_errors.load(r);
  s.light_late_max_ns = c.light_late_max_ns.load(r);
  s.frames_processed = c.frames_processed.load(r);
  s.frames_skipped = c.frames_skipped.load(r);
  s.estimator_failures = c.estimator_failures.load(r);
  s.frames_rejected = c.frames_rejected.load(r);
  for (std::size_t i = 0; i < kRejectReasonCount; ++i) s.frames_rejected_by[i] = c.frames_rejected_by[i].load(r);
  s.implausible_estimates = c.implausible_estimates.load(r);
  s.processing_max_ns = c.processing_max_ns.load(r);
  s.sender_ticks = c.sender_ticks.load(r);
  s.late_wakeups = c.late_wakeups.load(r);
  s.missed_ticks = c.missed_ticks.load(r);
  s.send_errors = c.send_errors.load(r);
  s.frames_sent = c.frames_sent.load(r);
  s.invalid_sent = c.invalid_sent.load(r);
  s.wakeup_late_max_ns = c.wakeup_late_max_ns.load(r);
  s.last_send_errno = c.last_send_errno.load(r);
  return s;
}

}  // namespace gvs::daemon
