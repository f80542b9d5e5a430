// The capture thread: frames from the source into the ring. Never blocks on
// another thread, never allocates, never logs: it counts.
//
// It also fires the LED ring and trigger ([light]): the frame timing lives
// here, and with an externally triggered global-shutter camera the trigger
// edge is what starts the frame the source then delivers, so the plan is
// fired right before the source is asked for the frame, once per frame, at
// the source's rate. A user-space-timed plan (gpio) holds the thread for the
// plan's length (a few ms at most, well inside a frame period).
#include <algorithm>
#include <array>
#include <span>

#include "gvs/drivers/clock.hpp"
#include "gvs/daemon/pipeline.hpp"

namespace gvs::daemon {

void Pipeline::capture_loop() noexcept {
  std::uint64_t applied_exposure = 0;
  std::uint64_t sequence = 0;
  std::int64_t expected_index = -1;
  const double fps = source_->nominal_fps();
  const std::int64_t period_ns = fps > 0.0 ? static_cast<std::int64_t>(1e9 / fps) : 100 * drivers::kNsPerMs;

  const std::uint64_t faults_before_loop = thread_page_faults();

  while (!stop_.load(std::memory_order_relaxed)) {
    bump(counters_.capture_heartbeat);
    counters_.capture_page_faults.store(thread_page_faults() - faults_before_loop, std::memory_order_relaxed);

    // Closed-loop exposure: the newest plan from the processing thread.
    const std::uint64_t version = exposure_request_.version();
    if (version != applied_exposure) {
      const core::ExposurePlan plan = exposure_request_.read();
      if (source_->controls_exposure()) {
        source_->set_exposure(plan);
        bump(counters_.exposure_updates);
      }
      if (light_ && !light_->arm(plan, static_cast<double>(period_ns) / 1e3)) bump(counters_.light_errors);
      applied_exposure = version;
    }
    if (light_) fire_light();

    drivers::FrameSlot* slot = ring_.try_claim();
    const bool overrun = slot == nullptr;
    if (overrun) slot = &spare_;

    slot->defect.reset();  // a source sets it only for a frame it could not deliver
    const drivers::SourceStatus status = source_->next(*slot, stop_);
    if (status == drivers::SourceStatus::stopped) break;
    if (status == drivers::SourceStatus::end) {
      source_ended_.store(true, std::memory_order_release);
      break;
    }
    if (status == drivers::SourceStatus::error) {
      bump(counters_.source_errors);
      drivers::sleep_until_ns(drivers::mono_now_ns() + drivers::kNsPerMs);  // do not spin on a failing source
      continue;
    }

    if (light_ && !light_->hardware_timed() && !source_->frames_carry_light()) stamp_light(*slot);
    slot->captured_ns = drivers::mono_now_ns();
    slot->sequence = ++sequence;
    bump(counters_.frames_captured);
    if (expected_index >= 0 && slot->view.index > expected_index) {
      bump(counters_.frames_dropped, static_cast<std::uint64_t>(slot->view.index - expected_index));
    }
    expected_index = slot->view.index + 1;
    const auto exposure_ns = static_cast<std::int64_t>(slot->view.exposure.exposure_us * 1000.0);
    if (slot->captured_ns - (slot->view.t_ns + exposure_ns) > period_ns) bump(counters_.capture_late);

    if (overrun) {
      bump(counters_.ring_overruns);
    } else {
      ring_.publish();
      frame_ready_.post();
    }
  }
  frame_ready_.post();  // let the processing thread notice the stop at once
}

void Pipeline::fire_light() noexcept {
  constexpr std::int64_t kLeadNs = 200'000;  // time to sleep to the first edge rather than be late for it
  const drivers::FireReport r = light_->fire(drivers::mono_now_ns() + kLeadNs);
  bump(counters_.light_plans);
  bump(counters_.light_edges, r.edges);
  if (r.late_edges > 0) bump(counters_.light_late_edges, r.late_edges);
  if (r.error) bump(counters_.light_errors);
  raise_max(counters_.light_late_max_ns, r.max_late_ns);
  // Keep the newest on-intervals, oldest first (a frame's exposure may span two fires).
  std::array<drivers::LitInterval, core::ExposurePlan::kMaxPulses + 1> fresh{};
  const std::size_t n = drivers::led_intervals(light_->last_edges(), fresh);
  for (std::size_t i = 0; i < n; ++i) {
    if (lit_count_ == lit_.size()) {
      std::copy(lit_.begin() + 1, lit_.end(), lit_.begin());
      --lit_count_;
    }
    lit_[lit_count_++] = fresh[i];
  }
}

void Pipeline::stamp_light(drivers::FrameSlot& slot) noexcept {
  // The camera said how long its shutter was open; the light is what the LED
  // ring's measured edges put inside that time. None: the frame is dark for
  // a reason the estimator must not guess at.
  core::ExposurePlan lit;
  const std::span<const drivers::LitInterval> history(lit_.data(), lit_count_);
  if (drivers::light_in_exposure(history, slot.view.t_ns, slot.view.exposure.exposure_us, lit)) {
    slot.view.exposure = lit;
  } else if (!slot.defect) {
    slot.defect = core::RejectReason::no_light_in_exposure;
  }
}

}  // namespace gvs::daemon
