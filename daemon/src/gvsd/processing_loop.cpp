// The processing thread: newest frame -> estimator -> plausibility gate ->
// latest estimate (seqlock) -> exposure controller -> next exposure plan (seqlock).
#include <algorithm>
#include <optional>

#include "gvs/drivers/clock.hpp"
#include "gvs/daemon/external_height.hpp"
#include "gvs/daemon/pipeline.hpp"

namespace gvs::daemon {

namespace {

bool same_plan(const core::ExposurePlan& a, const core::ExposurePlan& b) {
  if (a.exposure_us != b.exposure_us || a.pulse_count != b.pulse_count) return false;
  for (std::size_t i = 0; i < std::min(a.pulse_count, core::ExposurePlan::kMaxPulses); ++i) {
    if (a.pulses[i].start_us != b.pulses[i].start_us || a.pulses[i].duration_us != b.pulses[i].duration_us) {
      return false;
    }
  }
  return true;
}

}  // namespace

void Pipeline::processing_loop() noexcept {
  constexpr std::int64_t kIdleWaitNs = 20 * drivers::kNsPerMs;  // heartbeat and stop check without frames
  std::uint64_t published = 0;
  core::ExposurePlan plan = exposure_request_.read();

  const std::uint64_t faults_before_loop = thread_page_faults();

  while (!stop_.load(std::memory_order_relaxed)) {
    bump(counters_.processing_heartbeat);
    counters_.processing_page_faults.store(thread_page_faults() - faults_before_loop, std::memory_order_relaxed);
    std::uint64_t skipped = 0;
    drivers::FrameSlot* slot = ring_.take_newest(skipped);
    if (slot == nullptr) {
      frame_ready_.wait_for(kIdleWaitNs);
      continue;
    }
    if (skipped != 0) bump(counters_.frames_skipped, skipped);

    const std::int64_t t0 = drivers::mono_now_ns();
    core::VelocityEstimate e = estimator_->estimate(*slot);
    if (external_height_) {  // the sensor's velocity is scaled first, then moved to the reference point
      const std::uint64_t kept_before = height_history_.kept();
      if (height_receiver_) {
        height_receiver_->drain(height_history_);
        counters_.height_read_errors.store(height_receiver_->read_errors(), std::memory_order_relaxed);
      } else {
        hooks_.height_samples(height_history_);
      }
      bump(counters_.height_samples, height_history_.kept() - kept_before);
      const auto max_gap_ns = static_cast<std::int64_t>(config_.height.max_gap_ms * 1e6);
      if (const std::optional<double> h = height_history_.at(e.t_ns, max_gap_ns)) {
        (void)apply_external_height(e, *h, config_.height.nominal_mm);  // false: nominal scale, flagged
      }
      // Not counted: an estimate the laser dots scaled (they win).
      if (e.scale_source == core::ScaleSource::external) bump(counters_.height_scaled);
      if (e.scale_source == core::ScaleSource::nominal) bump(counters_.height_unscaled);
    }
    apply_lever_arm(e, config_.lever_arm_x_m, config_.lever_arm_y_m);
    const std::int64_t t1 = drivers::mono_now_ns();
    if (!e.has_speed) bump(e.has_direction ? counters_.direction_only : counters_.estimator_failures);
    const core::RejectCounts rejected = estimator_->rejected_frames();
    std::uint64_t rejected_total = 0;
    for (std::size_t i = 0; i < core::kRejectReasonCount; ++i) {
      counters_.frames_rejected_by[i].store(rejected[i], std::memory_order_relaxed);
      rejected_total += rejected[i];
    }
    counters_.frames_rejected.store(rejected_total, std::memory_order_relaxed);
    raise_max(counters_.processing_max_ns, t1 - t0);

    PublishedEstimate p;
    p.sequence = ++published;
    p.estimate = e;
    p.captured_ns = slot->captured_ns;
    p.published_ns = t1;
    p.processing_ns = t1 - t0;
    p.exposure_us = slot->view.exposure.exposure_us;
    // The gate judges only estimates that could go out valid: one below
    // min_quality is flagged by the sender anyway and must not move the track.
    if (can::quality_passes(e.quality, min_quality_.load(std::memory_order_relaxed))) {
      gate_.set_limits(plausibility_limits_.read());
      if (!publishable(gate_.check(e))) {
        p.plausible = false;
        bump(counters_.implausible_estimates);
      }
    }
    latest_.write(p);

    if (source_->controls_exposure()) {
      const ExposureSettings s = exposure_settings_.read();
      const core::ExposurePlan next = dsp::next_exposure(e, slot->view.exposure, plan, s.mode, s.limits);
      if (!same_plan(next, plan)) {
        plan = next;
        exposure_request_.write(plan);
      }
    }
    ring_.release();
    bump(counters_.frames_processed);
  }
}

}  // namespace gvs::daemon
