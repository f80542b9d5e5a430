// Pipeline set-up and tear-down: everything the real-time loops touch is
// made here, before the first frame.
#include "gvs/daemon/pipeline.hpp"
#include "gvs/daemon/external_height.hpp"

#include <pthread.h>

#include <algorithm>
#include <chrono>
#include <stdexcept>
#include <string>

#include "gvs/drivers/clock.hpp"

namespace gvs::daemon {

const char* role_name(ThreadRole role) {
  switch (role) {
    case ThreadRole::capture: return "capture";
    case ThreadRole::processing: return "processing";
    case ThreadRole::sender: return "sender";
  }
  return "?";
}

namespace {

std::vector<drivers::FrameSlot> make_slots(int count) {
  return std::vector<drivers::FrameSlot>(static_cast<std::size_t>(count));
}

can::EncoderConfig encoder_config(const DaemonConfig& c) {
  can::EncoderConfig e;
  e.base_id = c.base_id;
  return e;
}

}  // namespace

Pipeline::Pipeline(const DaemonConfig& config, std::unique_ptr<drivers::FrameSource> source,
                   std::unique_ptr<FrameEstimator> estimator, std::unique_ptr<can::CanSink> sink,
                   PipelineHooks hooks)
    : config_(config),
      source_(std::move(source)),
      estimator_(std::move(estimator)),
      sink_(std::move(sink)),
      light_(hooks.make_light ? hooks.make_light(config.light) : drivers::make_strobe_driver(config.light)),
      hooks_(std::move(hooks)),
      ring_(make_slots(config.ring_slots)),
      encoder_(encoder_config(config)),
      max_ticks_(hooks_.max_ticks),
      sink_events_(std::vector<can::SinkEvent>(64)) {
  if (!source_ || !estimator_ || !sink_) throw std::invalid_argument("Pipeline: source, estimator and CAN sink are required");
  if (config.status_period_ms % config.period_ms != 0) {
    throw std::invalid_argument("Pipeline: status_period_ms must be a multiple of period_ms");
  }
  if (config.align_to_frames) {
    const std::string refusal = slot_alignment_refusal(config.period_ms, source_->nominal_fps());
    if (!refusal.empty()) throw std::invalid_argument(refusal);
    phase_lock_.emplace(static_cast<std::int64_t>(config.period_ms) * drivers::kNsPerMs, source_->nominal_fps());
  }
  if (config.height.source == "can") {
    external_height_ = true;
    if (!hooks_.height_samples) {
      std::string iface = config.height.interface;
      if (iface.empty() && config.can_uri.rfind("socketcan:", 0) == 0) iface = config.can_uri.substr(10);
      height_receiver_ = std::make_unique<can::HeightReceiver>(iface, external_height_signal(config.height));
    }
  }
  core::ExposurePlan initial;
  initial.exposure_us = config.exposure_initial_us;
  exposure_request_.write(initial);
  apply_reloadable(config);

  for (drivers::FrameSlot& slot : ring_.slots_for_setup()) source_->prepare(slot);
  source_->prepare(spare_);
  if (hooks_.record_capacity > 0) {
    records_.wakeup_late_ns.resize(hooks_.record_capacity);
    records_.frame_to_can_ns.resize(hooks_.record_capacity);
    records_.frame_to_publish_ns.resize(hooks_.record_capacity);
  }
}

Pipeline::~Pipeline() {
  request_stop();
  join();
}

void Pipeline::apply_reloadable(const DaemonConfig& c) noexcept {
  staleness_ms_.store(static_cast<std::int64_t>(c.staleness_limit_ms), std::memory_order_relaxed);
  late_limit_ns_.store(static_cast<std::int64_t>(c.late_wakeup_limit_ms * 1e6), std::memory_order_relaxed);
  min_quality_.store(c.min_quality, std::memory_order_relaxed);
  plausibility_limits_.write(c.plausibility);
  ExposureSettings s;
  if (!dsp::parse_exposure_mode(c.exposure_mode.c_str(), s.mode)) s.mode = dsp::ExposureMode::fixed;
  // Two pulses need a strobe: a camera without a [light] driver exposes
  // continuously, so it gets the single-exposure controller instead.
  if (s.mode == dsp::ExposureMode::double_pulse && !light_ && !source_->frames_carry_light())
    s.mode = dsp::ExposureMode::adaptive;
  s.limits = dsp::exposure_limits_for(source_->geometry(), source_->nominal_fps());
  s.limits.max_exposure_us = c.exposure_max_us;
  source_->set_exposure_max_us(c.exposure_max_us);
  s.limits.min_pulse_us = c.exposure_min_pulse_us;
  // A camera without a strobe cannot expose shorter than its own floor: the
  // controller's sweep must turn round there, not below it.
  if (!light_ && !source_->frames_carry_light())
    s.limits.min_pulse_us = std::max(s.limits.min_pulse_us, c.libcamera_exposure_min_us);
  exposure_settings_.write(s);
}

void Pipeline::start() {
  if (!threads_.empty()) throw std::logic_error("Pipeline::start called twice");
  // The processing thread runs the estimator over these before the first
  // real frame (warm_up.hpp), then frees them.
  warm_up_frames_.emplace(source_->geometry());

  threads_.reserve(kThreadCount);
  threads_.emplace_back([this] { run_thread(ThreadRole::capture, config_.capture_thread); });
  threads_.emplace_back([this] { run_thread(ThreadRole::processing, config_.processing_thread); });
  threads_.emplace_back([this] { run_thread(ThreadRole::sender, config_.sender_thread); });
  while (threads_ready_.load(std::memory_order_acquire) < static_cast<int>(kThreadCount)) {
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
}

void Pipeline::run_thread(ThreadRole role, const ThreadConfig& config) {
  // Named for `ps -L`, `top -H` and tests: gvsd-capture, gvsd-processing,
  // gvsd-sender (at most 15 characters, the kernel's limit).
  (void)pthread_setname_np(pthread_self(), (std::string("gvsd-") + role_name(role)).c_str());
  reports_[static_cast<std::size_t>(role)] = setup_this_thread(config, config_.prefault_stack_kb);
  if (role == ThreadRole::processing) {
    // On this thread, at its priority: its own stack is touched too. Drawn
    // into the spare slot, which the capture thread uses only once every
    // thread is ready.
    warm_up(*estimator_, *warm_up_frames_, spare_);
    warm_up_frames_.reset();
  }
  if (hooks_.on_loop_start) hooks_.on_loop_start(role);
  threads_ready_.fetch_add(1, std::memory_order_acq_rel);
  // Start together: the sender reads every thread's set-up report.
  while (threads_ready_.load(std::memory_order_acquire) < static_cast<int>(kThreadCount)) {
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  switch (role) {
    case ThreadRole::capture: capture_loop(); break;
    case ThreadRole::processing: processing_loop(); break;
    case ThreadRole::sender: sender_loop(); break;
  }
}

void Pipeline::join() {
  for (std::thread& t : threads_) {
    if (t.joinable()) t.join();
  }
}

Progress Pipeline::progress() const noexcept {
  Progress p;
  p.beats[0] = counters_.capture_heartbeat.load(std::memory_order_relaxed);
  p.beats[1] = counters_.processing_heartbeat.load(std::memory_order_relaxed);
  p.beats[2] = counters_.sender_heartbeat.load(std::memory_order_relaxed);
  return p;
}

bool Pipeline::realtime() const noexcept {
  const ThreadConfig* wanted[] = {&config_.capture_thread, &config_.processing_thread, &config_.sender_thread};
  for (std::size_t i = 0; i < kThreadCount; ++i) {
    if (wanted[i]->priority > 0 && !reports_[i].fifo) return false;
  }
  return true;
}

}  // namespace gvs::daemon

namespace gvs::daemon {

bool Pipeline::pop_sink_event(can::SinkEvent& out) noexcept {
  const can::SinkEvent* e = sink_events_.take_oldest();
  if (e == nullptr) return false;
  out = *e;
  sink_events_.release();
  return true;
}

}  // namespace gvs::daemon
