// Counters the real-time threads bump instead of logging. Each counter has
// exactly one writing thread; the main thread reads them for the health line
// and the sender copies them into the status message.
#pragma once

#include <array>
#include <atomic>
#include <cstdint>

#include "gvs/core/reject_reason.hpp"

namespace gvs::daemon {

/// Increments a single-writer counter (no read-modify-write bus lock needed).
inline void bump(std::atomic<std::uint64_t>& c, std::uint64_t by = 1) noexcept {
  c.store(c.load(std::memory_order_relaxed) + by, std::memory_order_relaxed);
}
/// Raises a single-writer maximum.
inline void raise_max(std::atomic<std::int64_t>& m, std::int64_t v) noexcept {
  if (v > m.load(std::memory_order_relaxed)) m.store(v, std::memory_order_relaxed);
}

/// Where a counter is shown in the health line (format_health_line).
enum class HealthGroup : std::uint8_t { capture, processing, can, exposure, light, height, none };

enum class HealthShow : std::uint8_t {
  value,    ///< the text with the value
  delta,    ///< the text, then the change since the previous line: "ring overruns 2 (+2)"
  delta_by_reason,  ///< as delta, then each core::RejectReason that occurred: "rejected 3 (+1) [unreadable 1 (+0), ...]"
  nonzero,  ///< the text only when the value is not 0
  hidden,   ///< not in the line (heartbeats for the watchdog, the sender's own tick count)
};

// Every health counter, declared once:
//   X(name, type, writing thread, group in the line, how it is shown, text, unit, help)
// The text is a fmt template: {v} the value, {rate:.1f} the change per second,
// {ms:.2f} a nanosecond value in milliseconds. HealthCounters, HealthSnapshot,
// snapshot(), kHealthFields and the health line are all made from this list.
// Types: std::uint64_t counts, std::int64_t maxima (ns), int for an errno.
#define GVS_HEALTH_COUNTERS(X)                                                                                      \
  X(frames_captured, std::uint64_t, capture, capture, value, "{v} frames ({rate:.1f} fps)", "frames",               \
    "frames the source delivered")                                                                                \
  X(ring_overruns, std::uint64_t, capture, capture, delta, "ring overruns {v}", "frames",                           \
    "frames lost because every slot was busy")                                                                    \
  X(frames_dropped, std::uint64_t, capture, capture, delta, "source dropped {v}", "frames",                         \
    "frames the camera never delivered (gaps in its frame index); gvsd's own losses are ring overruns and skipped") \
  X(source_errors, std::uint64_t, capture, capture, delta, "source errors {v}", "frames",                           \
    "frames the source could not read")                                                                           \
  X(capture_late, std::uint64_t, capture, capture, value, "late {v}", "frames",                                    \
    "frames delivered more than a period late")                                                                   \
  X(exposure_updates, std::uint64_t, capture, exposure, value, "exposure updates {v}", "plans",                    \
    "exposure plans applied to the source")                                                                       \
  X(capture_page_faults, std::uint64_t, capture, capture, delta, "page faults {v}", "faults",                      \
    "page faults of the capture thread in its loop (a page first touched, or one not locked)")                    \
  X(capture_heartbeat, std::uint64_t, capture, none, hidden, "", "attempts", "capture loop progress (watchdog)")   \
  X(light_plans, std::uint64_t, capture, light, value, "{v} plans", "frames",                                      \
    "frames whose exposure plan the [light] driver fired")                                                        \
  X(light_edges, std::uint64_t, capture, light, value, "{v} edges", "edges", "output edges driven")                \
  X(light_late_edges, std::uint64_t, capture, light, delta, "late edges {v}", "edges",                             \
    "edges later than [light] late_limit_us")                                                                     \
  X(light_errors, std::uint64_t, capture, light, delta, "errors {v}", "errors",                                    \
    "failed set-value / sysfs writes, plans the driver refused")                                                  \
  X(light_late_max_ns, std::int64_t, capture, light, value, "max lateness {ms:.3f} ms", "ns",                      \
    "latest edge so far")                                                                                         \
  X(frames_processed, std::uint64_t, processing, processing, value, "{v} frames", "frames",                        \
    "frames the estimator ran on")                                                                                \
  X(frames_skipped, std::uint64_t, processing, processing, delta, "skipped {v}", "frames",                         \
    "older frames passed over for the newest")                                                                    \
  X(frames_rejected, std::uint64_t, processing, processing, delta_by_reason, "rejected {v}", "frames",            \
    "bad input frames (unreadable, wrong size or exposure, time backwards)")                                      \
  X(estimator_failures, std::uint64_t, processing, processing, delta, "no estimate {v}", "frames",                 \
    "frames that gave neither a speed nor a direction (rejected input included)")                                 \
  X(direction_only, std::uint64_t, processing, processing, delta, "direction only {v}", "frames",                  \
    "frames that gave a direction but no speed (e.g. a streak longer than the frame measures)")                   \
  X(implausible_estimates, std::uint64_t, processing, processing, delta, "implausible {v}", "estimates",           \
    "held back by the plausibility gate")                                                                         \
  X(processing_max_ns, std::int64_t, processing, processing, value, "max {ms:.2f} ms", "ns",                       \
    "longest estimate so far")                                                                                    \
  X(processing_page_faults, std::uint64_t, processing, processing, delta, "page faults {v}", "faults",             \
    "page faults of the processing thread in its loop")                                                           \
  X(processing_heartbeat, std::uint64_t, processing, none, hidden, "", "loops",                                    \
    "processing loop progress (watchdog)")                                                                        \
  X(height_samples, std::uint64_t, processing, height, value, "{v} samples", "samples",                          \
    "readings of the [height] source = \"can\" distance sensor received")                                         \
  X(height_read_errors, std::uint64_t, processing, height, delta, "read errors {v}", "reads",                     \
    "failed reads of the [height] CAN socket")                                                                    \
  X(height_scaled, std::uint64_t, processing, height, delta, "scaled {v}", "estimates",                           \
    "estimates scaled by the sensor's height")                                                                    \
  X(height_unscaled, std::uint64_t, processing, height, delta, "nominal {v}", "estimates",                        \
    "estimates left at the nominal scale: no reading within [height] max_gap_ms, or one beyond 25 % of nominal")  \
  X(frames_sent, std::uint64_t, sender, can, value, "{v} frames sent", "CAN frames", "CAN frames written")         \
  X(invalid_sent, std::uint64_t, sender, can, delta, "{v} flagged invalid", "messages",                            \
    "velocity messages flagged invalid (stale, no estimate, low quality, implausible)")                           \
  X(send_errors, std::uint64_t, sender, can, delta, "send errors {v}", "CAN frames", "CAN frames not written")      \
  X(last_send_errno, int, sender, can, nonzero, "last errno {v}", "errno", "the last send error's errno")            \
  X(late_wakeups, std::uint64_t, sender, can, delta, "late wake-ups {v}", "periods",                               \
    "woke later than [can] late_wakeup_limit_ms")                                                                 \
  X(missed_ticks, std::uint64_t, sender, can, value, "missed periods {v}", "periods", "whole periods skipped")     \
  X(wakeup_late_max_ns, std::int64_t, sender, can, value, "max lateness {ms:.3f} ms", "ns",                        \
    "latest wake-up so far")                                                                                      \
  X(sender_page_faults, std::uint64_t, sender, can, delta, "page faults {v}", "faults",                            \
    "page faults of the CAN sender thread in its loop")                                                           \
  X(sender_ticks, std::uint64_t, sender, none, hidden, "", "periods", "periods the sender ran")                    \
  X(sender_heartbeat, std::uint64_t, sender, none, hidden, "", "periods", "sender loop progress (watchdog)")

/// The counters the threads write: one writing thread each.
struct HealthCounters {
#define GVS_HEALTH_ATOMIC(name, type, thread, group, show, text, unit, help) std::atomic<type> name{0};
  GVS_HEALTH_COUNTERS(GVS_HEALTH_ATOMIC)
#undef GVS_HEALTH_ATOMIC
  /// frames_rejected per core::RejectReason (processing thread).
  std::array<std::atomic<std::uint64_t>, core::kRejectReasonCount> frames_rejected_by{};
};

/// A plain copy of the counters at one moment.
struct HealthSnapshot {
#define GVS_HEALTH_VALUE(name, type, thread, group, show, text, unit, help) type name = 0;
  GVS_HEALTH_COUNTERS(GVS_HEALTH_VALUE)
#undef GVS_HEALTH_VALUE
  core::RejectCounts frames_rejected_by{};
};

inline HealthSnapshot snapshot(const HealthCounters& c) noexcept {
  HealthSnapshot s;
#define GVS_HEALTH_COPY(name, type, thread, group, show, text, unit, help) s.name = c.name.load(std::memory_order_relaxed);
  GVS_HEALTH_COUNTERS(GVS_HEALTH_COPY)
#undef GVS_HEALTH_COPY
  for (std::size_t i = 0; i < core::kRejectReasonCount; ++i) {
    s.frames_rejected_by[i] = c.frames_rejected_by[i].load(std::memory_order_relaxed);
  }
  return s;
}

/// One declared counter, for the health line and its documentation.
struct HealthField {
  const char* name;
  const char* thread;  ///< the one thread that writes it
  HealthGroup group;
  HealthShow show;
  const char* text;  ///< fmt template: {v}, {rate}, {ms}
  const char* unit;
  const char* help;
  std::int64_t (*value)(const HealthSnapshot&) noexcept;
};

inline constexpr HealthField kHealthFields[] = {
#define GVS_HEALTH_FIELD(name, type, thread, group, show, text, unit, help)                                   \
  {#name, #thread, HealthGroup::group, HealthShow::show, text, unit, help,                                   \
   [](const HealthSnapshot& s) noexcept { return static_cast<std::int64_t>(s.name); }},
    GVS_HEALTH_COUNTERS(GVS_HEALTH_FIELD)
#undef GVS_HEALTH_FIELD
};

}  // namespace gvs::daemon
