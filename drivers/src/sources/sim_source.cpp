// `sim:SCENARIO`: the simulator as a camera. It loops the scenario, renders
// straight into the ring slot's preallocated pixels and delivers each frame
// at the end of its exposure, paced in real time at the frame rate.
#include "gvs/drivers/sim_source.hpp"

#include <sstream>
#include <stdexcept>

#include "gvs/drivers/clock.hpp"

namespace gvs::drivers {

SimSource::SimSource(const SimulatorConfig& config) : sim_(config), config_(config) {
  period_ns_ = static_cast<std::int64_t>(1e9 / config.fps);
  plan_.exposure_us = config.exposure_us;
  // Render frame 0 now so every buffer inside the simulator and the scratch
  // record has its final size before the real-time loop; a second render,
  // with warm buffers and caches, gives the first render-time estimate.
  sim_.render(0, plan_, scratch_);
  const std::int64_t t0 = mono_now_ns();
  sim_.render(1, plan_, scratch_);
  render_ns_ = mono_now_ns() - t0;
}

std::string SimSource::describe() const {
  std::ostringstream s;
  s << "sim:" << config_.scenario << " (" << config_.fps << " fps, " << config_.camera.width_px << 'x'
    << config_.camera.height_px << " px, looping";
  if (sim_.config().ground != "procedural") s << ", ground " << sim_.config().ground;
  s << ')';
  return s.str();
}

std::string SimSource::health_text() const {
  const double render_ms = static_cast<double>(render_ns_shown_.load(std::memory_order_relaxed)) / 1e6;
  const double period_ms = static_cast<double>(period_ns_) / 1e6;
  if (render_ms <= period_ms) return {};
  std::ostringstream s;
  s.setf(std::ios::fixed);
  s.precision(1);
  s << "sim: renders " << render_ms << " ms per frame, ";
  s.precision(0);
  s << 1000.0 / render_ms << " of " << config_.fps
    << " fps on this machine: the frames it cannot render in time are dropped, as a camera drops them";
  return s.str();
}

void SimSource::prepare(FrameSlot& slot) {
  slot.view.gray.create(config_.camera.height_px, config_.camera.width_px, CV_8UC1);
  slot.view.gray.setTo(0);  // touch every page now
}

SourceStatus SimSource::next(FrameSlot& slot, const std::atomic<bool>& stop) noexcept {
  // A camera exposes frame k during [base + k*T, base + k*T + exposure] and
  // delivers it at the end, whether or not anyone is ready for it. Pick the
  // first frame whose delivery is still ahead once it is rendered; frames the
  // renderer is too slow for are skipped, as a real camera drops them, and
  // show up as index gaps (counted as dropped). Timestamps stay exact.
  const std::int64_t now = mono_now_ns();
  const auto exposure_ns = static_cast<std::int64_t>(plan_.exposure_us * 1000.0);
  // Margin for a render slower than the estimate (cache, memory bus).
  constexpr std::int64_t kMarginNs = 1'000'000;
  if (base_ns_ < 0) base_ns_ = now + render_ns_ + kMarginNs;  // frame 0 in time: none dropped at start
  std::int64_t k = next_index_;
  const std::int64_t ready_ns = now + render_ns_ + kMarginNs;
  const std::int64_t due_k = base_ns_ + k * period_ns_ + exposure_ns;
  if (due_k < ready_ns) k += (ready_ns - due_k + period_ns_ - 1) / period_ns_;

  const std::int64_t t0 = mono_now_ns();
  try {
    scratch_.gray = slot.view.gray;  // render in place: shares the slot's buffer (no allocation)
    sim_.render(k, plan_, scratch_);
  } catch (...) {
    next_index_ = k + 1;
    return SourceStatus::error;
  }
  const std::int64_t took = mono_now_ns() - t0;
  if (rendered_live_) {
    render_ns_ = (render_ns_ * 7 + took) / 8;
    if (took > render_ns_) render_ns_ = took;  // follow slow-downs at once, speed-ups slowly
  } else {
    // The constructor's render ran before the real-time setup (normal
    // priority, cold): the first real-time render replaces its estimate.
    render_ns_ = took;
    rendered_live_ = true;
  }
  render_ns_shown_.store(render_ns_, std::memory_order_relaxed);
  if (scratch_.gray.data != slot.view.gray.data) {
    // The simulator replaced the buffer (it should not): copy into the slot.
    if (scratch_.gray.size() != slot.view.gray.size() || scratch_.gray.type() != slot.view.gray.type()) {
      return SourceStatus::error;
    }
    scratch_.gray.copyTo(slot.view.gray);
  }
  next_index_ = k + 1;

  const std::int64_t exposure_start_ns = base_ns_ + k * period_ns_;
  if (!sleep_until_or_stop(exposure_start_ns + exposure_ns, stop)) return SourceStatus::stopped;

  slot.view.index = k;
  slot.view.t_ns = exposure_start_ns;
  slot.view.exposure = plan_;
  const TruthRecord& t = scratch_.truth;
  slot.truth.known = true;
  slot.truth.vx_mps = t.vx_mps;
  slot.truth.vy_mps = t.vy_mps;
  slot.truth.speed_mps = t.speed_mps;
  slot.truth.direction_deg = t.direction_deg.value_or(0.0);
  slot.truth.yaw_rate_dps = t.yaw_rate_dps;
  return SourceStatus::frame;
}

void SimSource::set_exposure(const core::ExposurePlan& plan) noexcept {
  try {
    sim_.set_exposure(plan);  // checks the plan against the frame period
    plan_ = plan;
  } catch (...) {
    // an impossible plan: keep the previous one
  }
}

}  // namespace gvs::drivers
