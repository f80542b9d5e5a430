// The capture thread: frames from the source into the ring. Never blocks on
// another thread, never allocates, never logs: it counts.
#include "gvs/daemon/clock.hpp"
#include "gvs/daemon/pipeline.hpp"

namespace gvs::daemon {

void Pipeline::capture_loop() noexcept {
  std::uint64_t applied_exposure = 0;
  std::uint64_t sequence = 0;
  std::int64_t expected_index = -1;
  const double fps = source_->nominal_fps();
  const std::int64_t period_ns = fps > 0.0 ? static_cast<std::int64_t>(1e9 / fps) : 100 * kNsPerMs;

  while (!stop_.load(std::memory_order_relaxed)) {
    bump(counters_.capture_heartbeat);

    // Closed-loop exposure: the newest plan from the processing thread.
    const std::uint64_t version = exposure_request_.version();
    if (version != applied_exposure && source_->controls_exposure()) {
      source_->set_exposure(exposure_request_.read());
      applied_exposure = version;
      bump(counters_.exposure_updates);
    }

    FrameSlot* slot = ring_.try_claim();
    const bool overrun = slot == nullptr;
    if (overrun) slot = &spare_;

    slot->defect = nullptr;  // a source sets it only for a frame it could not deliver
    const SourceStatus status = source_->next(*slot, stop_);
    if (status == SourceStatus::stopped) break;
    if (status == SourceStatus::end) {
      source_ended_.store(true, std::memory_order_release);
      break;
    }
    if (status == SourceStatus::error) {
      bump(counters_.source_errors);
      sleep_until_ns(mono_now_ns() + kNsPerMs);  // do not spin on a failing source
      continue;
    }

    slot->captured_ns = mono_now_ns();
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

}  // namespace gvs::daemon
