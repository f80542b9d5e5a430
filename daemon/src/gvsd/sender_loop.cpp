// The CAN sender: wakes on an absolute schedule (clock_nanosleep with
// TIMER_ABSTIME, so lateness never accumulates), packs the latest estimate
// and its age, and every status period the status and timing messages.
// Stale or missing estimates go out with their Valid bits cleared. Every
// period: GVS_Velocity, GVS_VelocityXY and GVS_RideHeight.
#include <array>

#include "gvs/daemon/bus_estimate.hpp"
#include "gvs/drivers/clock.hpp"
#include "gvs/daemon/pipeline.hpp"

namespace gvs::daemon {

namespace {

std::uint8_t low_byte(std::uint64_t v) { return static_cast<std::uint8_t>(v & 0xFFU); }

}  // namespace

void Pipeline::send_frame(const can::CanFrame& frame) noexcept {
  if (sink_->send(frame) == can::SendResult::Ok) {
    bump(counters_.frames_sent);
  } else {
    bump(counters_.send_errors);
    counters_.last_send_errno.store(sink_->counters().last_errno, std::memory_order_relaxed);
  }
}

void Pipeline::collect_sink_events() noexcept {
  std::array<can::SinkEvent, 8> events{};
  const std::size_t n = sink_->poll_events(events);
  for (std::size_t i = 0; i < n; ++i) {
    can::SinkEvent* slot = sink_events_.try_claim();
    if (slot == nullptr) {
      bump(sink_events_lost_);
      continue;
    }
    *slot = events[i];
    sink_events_.publish();
  }
}

can::StatusMsg Pipeline::make_status(const PublishedEstimate& latest, const can::VelocityPair& sent) noexcept {
  const HealthSnapshot now = snapshot(counters_);
  const bool fresh = sent.fresh;
  can::StatusMsg m;
  const bool camera_fault = now.frames_captured == status_last_.frames_captured ||
                            now.source_errors != status_last_.source_errors;
  if (camera_fault) m.faults |= can::kFaultCamera;
  if (!fresh) m.faults |= can::kFaultEstimateStale;
  if (now.ring_overruns != status_last_.ring_overruns) m.faults |= can::kFaultRingOverrun;
  if (now.late_wakeups != status_last_.late_wakeups || now.missed_ticks != status_last_.missed_ticks) {
    m.faults |= can::kFaultDeadlineMiss;
  }
  if (now.send_errors != status_last_.send_errors) m.faults |= can::kFaultCanSendError;
  if (!realtime()) m.faults |= can::kFaultNoRealtime;
  if (now.implausible_estimates != status_last_.implausible_estimates) m.faults |= can::kFaultImplausible;
  if (now.light_errors != status_last_.light_errors) m.faults |= can::kFaultLight;
  if (latest.sequence != 0 && latest.estimate.scale_source == core::ScaleSource::nominal) {
    m.faults |= can::kFaultScaleUncorrected;
  }
  m.faults = static_cast<std::uint16_t>(m.faults | sink_->take_fault_bits());

  if (stop_.load(std::memory_order_relaxed)) {
    m.state = can::SensorState::Stopping;
  } else if (latest.sequence == 0) {
    m.state = can::SensorState::Init;
  } else if (camera_fault && !fresh) {
    m.state = can::SensorState::Fault;
  } else if (sent.velocity.valid) {
    m.state = can::SensorState::Running;
  } else {
    m.state = can::SensorState::Degraded;
  }
  m.dropped_frames = low_byte(now.frames_dropped + now.frames_skipped);
  m.ring_overruns = low_byte(now.ring_overruns);
  m.can_send_errors = low_byte(now.send_errors);
  m.method = bus_estimate(latest.estimate).method_code;
  status_last_ = now;
  return m;
}

void Pipeline::sender_loop() noexcept {
  const std::int64_t period_ns = config_.period_ms * drivers::kNsPerMs;
  const int status_every = config_.status_period_ms / config_.period_ms;
  std::uint64_t last_sequence = 0;
  std::int64_t tick_sent = 0;  // periods actually sent
  status_last_ = snapshot(counters_);
  std::int64_t next_ns = drivers::mono_now_ns() + period_ns;

  const std::uint64_t faults_before_loop = thread_page_faults();

  for (;;) {
    drivers::sleep_until_ns(next_ns);
    const std::int64_t woke_ns = drivers::mono_now_ns();
    bump(counters_.sender_heartbeat);
    counters_.sender_page_faults.store(thread_page_faults() - faults_before_loop, std::memory_order_relaxed);
    const PublishedEstimate latest = latest_.read();

    if (stop_.load(std::memory_order_relaxed)) {  // tell the ECU we are going
      send_frame(encoder_.status(make_status(latest, can::VelocityPair{})));
      collect_sink_events();
      break;
    }
    bump(counters_.sender_ticks);
    const std::int64_t sent_ticks = tick_sent++;
    const std::int64_t late_ns = woke_ns - next_ns;
    raise_max(counters_.wakeup_late_max_ns, late_ns);
    if (late_ns > late_limit_ns_.load(std::memory_order_relaxed)) bump(counters_.late_wakeups);
    if (records_.wakeups < records_.wakeup_late_ns.size()) records_.wakeup_late_ns[records_.wakeups++] = late_ns;

    const can::BusEstimate bus = bus_estimate(latest.estimate);
    const can::ValidityRule rule{staleness_ms_.load(std::memory_order_relaxed),
                                 min_quality_.load(std::memory_order_relaxed)};
    can::CanFrame velocity_frame;
    can::CanFrame xy_frame;
    const can::VelocityPair pair = encoder_.estimate_frames(latest.sequence != 0 ? &bus : nullptr, woke_ns, rule,
                                                            latest.plausible, velocity_frame, xy_frame);
    send_frame(velocity_frame);
    send_frame(xy_frame);
    send_frame(encoder_.ride_height(can::ride_height_from_estimate(latest.sequence != 0 ? &bus : nullptr, woke_ns, rule)));
    if (!pair.velocity.valid) bump(counters_.invalid_sent);

    if (latest.sequence != last_sequence) {
      last_sequence = latest.sequence;
      if (phase_lock_) phase_lock_->on_estimate(latest.captured_ns, latest.published_ns);
      const std::int64_t sent_ns = drivers::mono_now_ns();
      if (records_.estimates < records_.frame_to_can_ns.size()) {
        records_.frame_to_can_ns[records_.estimates] = sent_ns - latest.captured_ns;
        records_.frame_to_publish_ns[records_.estimates] = latest.published_ns - latest.captured_ns;
        ++records_.estimates;
      }
    }

    // Status and timing with every status_every-th velocity message sent
    // (counted in messages, not grid slots: a period missed in a stall
    // delays the next status by that period, and a bounded run sends
    // exactly its share).
    if (sent_ticks % status_every == 0) {
      send_frame(encoder_.status(make_status(latest, pair)));
      can::TimingMsg timing;
      timing.exposure_us = static_cast<std::uint32_t>(latest.exposure_us);
      timing.processing_time_us = static_cast<std::uint32_t>(latest.processing_ns / 1000);
      timing.late_wakeups = low_byte(counters_.late_wakeups.load(std::memory_order_relaxed));
      send_frame(encoder_.timing(timing));
    }
    collect_sink_events();  // also flushes a candump log
    if (max_ticks_ > 0 && counters_.sender_ticks.load(std::memory_order_relaxed) >= max_ticks_) {
      run_complete_.store(true, std::memory_order_release);  // --run-for: exactly max_ticks periods
      break;
    }

    next_ns += period_ns;
    if (phase_lock_) next_ns = phase_lock_->adjust(next_ns);
    const std::int64_t now = drivers::mono_now_ns();
    if (next_ns <= now) {  // overslept whole periods: skip them, keep the phase
      const std::int64_t missed = (now - next_ns) / period_ns + 1;
      bump(counters_.missed_ticks, static_cast<std::uint64_t>(missed));
      next_ns += missed * period_ns;
    }
  }
}

}  // namespace gvs::daemon
