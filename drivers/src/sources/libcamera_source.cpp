// `libcamera[:ID]`: see gvs/drivers/libcamera_source.hpp for the threads.
#include "gvs/drivers/libcamera_source.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <chrono>
#include <sstream>
#include <stdexcept>
#include <thread>

#include "gvs/drivers/clock.hpp"

namespace gvs::drivers {

namespace {

/// Counters have one writing thread each: no read-modify-write needed.
void bump(std::atomic<std::uint64_t>& c, std::uint64_t by = 1) noexcept {
  c.store(c.load(std::memory_order_relaxed) + by, std::memory_order_relaxed);
}

std::uint64_t pack(const CameraControls& c) {
  return static_cast<std::uint64_t>(static_cast<std::uint32_t>(c.exposure_us)) |
         (static_cast<std::uint64_t>(std::bit_cast<std::uint32_t>(c.analogue_gain)) << 32U);
}

}  // namespace

std::string choose_camera(const std::vector<std::string>& ids, const std::string& wanted) {
  if (ids.empty()) {
    throw std::runtime_error(
        "libcamera: no camera found. Check the camera's cable and that its kernel driver is loaded "
        "(ls /dev/video* /dev/media*, dmesg), that this user may open them (group video), or run "
        "without a camera with [source] uri = \"sim:sine\" or \"replay:DIR\"");
  }
  if (wanted.empty()) return ids.front();
  if (std::find(ids.begin(), ids.end(), wanted) != ids.end()) return wanted;
  std::string present;
  for (const auto& id : ids) present += (present.empty() ? "'" : ", '") + id + "'";
  throw std::runtime_error("libcamera: camera '" + wanted + "' not found; cameras present: " + present +
                           ". Set [source] uri = \"libcamera:<one of them>\", or \"libcamera\" for the first");
}

CameraControls camera_controls_for(const core::ExposurePlan& plan, const LibcameraSettings& s) {
  return camera_controls_for(plan, s, s.exposure_max_us);
}

CameraControls camera_controls_for(const core::ExposurePlan& plan, const LibcameraSettings& s,
                                            double exposure_max_us) {
  const double period_us = 1e6 / s.fps;
  const double longest_us = std::max(s.exposure_min_us, std::min(exposure_max_us, 0.9 * period_us));
  const double exposure_us = std::clamp(plan.exposure_us, s.exposure_min_us, longest_us);
  const double gain = std::clamp(s.gain_min * exposure_max_us / exposure_us, s.gain_min, s.gain_max);
  CameraControls c;
  c.exposure_us = static_cast<std::int32_t>(std::lround(exposure_us));
  c.analogue_gain = static_cast<float>(gain);
  c.frame_duration_us = std::llround(period_us);
  return c;
}

LibcameraSource::LibcameraSource(std::unique_ptr<CameraDevice> device, const LibcameraSettings& settings)
    : device_(std::move(device)),
      settings_(settings),
      // Room for every buffer of a stream, and as many again from a stream a restart retired.
      completed_(std::vector<Completed>(2 * static_cast<std::size_t>(std::max(2, settings.buffer_count)))),
      copied_(std::vector<Copied>(2 * static_cast<std::size_t>(std::max(2, settings.buffer_count)))) {
  period_ns_ = static_cast<std::int64_t>(1e9 / settings_.fps);
  plan_.exposure_us = settings_.exposure_initial_us;
  exposure_max_us_.store(settings_.exposure_max_us);
  apply_exposure(settings_.exposure_max_us);
  camera_id_ = choose_camera(device_->list_cameras(), settings_.camera_id);
  open_and_start();
  supervisor_ = std::thread([this] { supervise(); });
}

LibcameraSource::~LibcameraSource() {
  quit_.store(true);
  supervisor_wake_.post();
  if (supervisor_.joinable()) supervisor_.join();
  device_->stop();  // the camera thread's last callbacks return before this does
  device_->close();
}

void LibcameraSource::open_and_start() {
  device_->open(camera_id_);
  CameraStreamRequest want;
  want.width_px = settings_.camera.width_px;
  want.height_px = settings_.camera.height_px;
  want.pixel_format = settings_.pixel_format;
  want.buffer_count = settings_.buffer_count;
  const CameraStreamInfo got = device_->configure(want);
  if (got.width_px != want.width_px || got.height_px != want.height_px ||
      got.stride_bytes < static_cast<std::size_t>(want.width_px)) {
    device_->close();
    throw std::runtime_error("libcamera: camera '" + camera_id_ + "' configured " + std::to_string(got.width_px) +
                             "x" + std::to_string(got.height_px) + " (stride " + std::to_string(got.stride_bytes) +
                             "), not the " + std::to_string(want.width_px) + "x" + std::to_string(want.height_px) +
                             " of [camera] width_px/height_px");
  }
  // The camera thread is not running yet: start() happens-before its callbacks.
  stream_generation_ = generation_.load();
  max_held_ = std::min(std::max(got.buffer_count, 2), static_cast<int>(copied_.capacity() / 2)) - 1;
  held_.store(0);
  new_stream_ = true;
  device_->start(current_controls(), *this);
  stream_started_ns_.store(mono_now_ns());
  streaming_.store(true);
}

std::string LibcameraSource::describe() const {
  std::ostringstream s;
  s << "libcamera:" << camera_id_ << " (" << device_->describe() << ", " << settings_.camera.width_px << 'x'
    << settings_.camera.height_px << ' ' << camera_pixel_format_name(settings_.pixel_format) << ", "
    << settings_.fps << " fps, manual exposure)";
  return s.str();
}

void LibcameraSource::prepare(FrameSlot& slot) {
  slot.view.gray.create(settings_.camera.height_px, settings_.camera.width_px, CV_8UC1);
  slot.view.gray.setTo(0);
}

CameraControls LibcameraSource::current_controls() const noexcept {
  const std::uint64_t p = controls_packed_.load(std::memory_order_acquire);
  CameraControls c;
  c.exposure_us = static_cast<std::int32_t>(static_cast<std::uint32_t>(p & 0xFFFFFFFFU));
  c.analogue_gain = std::bit_cast<float>(static_cast<std::uint32_t>(p >> 32U));
  c.frame_duration_us = std::llround(1e6 / settings_.fps);
  return c;
}

void LibcameraSource::set_exposure(const core::ExposurePlan& plan) noexcept {
  plan_ = plan;
  apply_exposure(exposure_max_us_.load(std::memory_order_relaxed));
}

void LibcameraSource::set_exposure_max_us(double exposure_max_us) noexcept {
  exposure_max_us_.store(exposure_max_us, std::memory_order_relaxed);
}

void LibcameraSource::apply_exposure(double exposure_max_us) noexcept {
  applied_exposure_max_us_ = exposure_max_us;
  controls_packed_.store(pack(camera_controls_for(plan_, settings_, exposure_max_us)), std::memory_order_release);
}

// ---- camera library's thread: hand the request over (or re-queue it); no pixel copy ----

void LibcameraSource::request_completed(const CompletedRequest& done) noexcept {
  if (done.cancelled) {
    bump(counters_.requests_cancelled);
    return;  // the camera is stopping: the request is not queued again
  }
  const auto width = static_cast<std::size_t>(settings_.camera.width_px);
  const auto height = static_cast<std::size_t>(settings_.camera.height_px);
  const bool complete = done.buffer_ok && done.luma != nullptr && done.stride_bytes >= width &&
                        done.bytes_used >= done.stride_bytes * (height - 1) + width;
  if (new_stream_) {
    index_base_ = last_index_ + 1 - static_cast<std::int64_t>(done.sequence);
    last_sequence_ = done.sequence;
    new_stream_ = false;
  } else if (done.sequence > last_sequence_ + 1) {
    bump(counters_.sequence_gaps, done.sequence - last_sequence_ - 1);
  }
  if (done.sequence > last_sequence_ || last_index_ < 0) last_sequence_ = done.sequence;

  if (!complete) {
    bump(counters_.requests_incomplete);
    requeue(done.buffer_index);
    return;
  }
  Completed* c = held_.load(std::memory_order_acquire) < max_held_ ? completed_.try_claim() : nullptr;
  if (c == nullptr) {
    bump(counters_.handoff_full);
    requeue(done.buffer_index);
    return;
  }
  c->buffer_index = done.buffer_index;
  c->generation = stream_generation_;
  c->luma = done.luma;
  c->stride_bytes = done.stride_bytes;
  c->index = index_base_ + static_cast<std::int64_t>(done.sequence);
  last_index_ = std::max(last_index_, c->index);
  c->t_ns = done.sensor_timestamp_ns;
  c->exposure_us = done.exposure_us;
  c->defect.reset();
  if (done.exposure_us <= 0) {
    bump(counters_.no_exposure_metadata);
    c->defect = core::RejectReason::no_exposure_metadata;  // never guess the exposure the speed is measured with
  }
  if (done.sensor_timestamp_ns <= last_t_ns_ || done.sensor_timestamp_ns < 0) {
    bump(counters_.timestamps_backwards);
    c->defect = core::RejectReason::time_backwards;
  } else {
    last_t_ns_ = done.sensor_timestamp_ns;
  }
  held_.fetch_add(1, std::memory_order_acq_rel);  // only this thread adds: the check above stays true
  completed_.publish();
  bump(counters_.frames_delivered);
  frame_ready_.post();
}

void LibcameraSource::requeue(std::uint32_t buffer_index) noexcept {
  // Two threads re-queue (this one, the supervisor): a read-modify-write count.
  if (!device_->queue(buffer_index, current_controls())) {
    counters_.requeue_failures.fetch_add(1, std::memory_order_relaxed);
  }
}

void LibcameraSource::camera_disconnected() noexcept {
  // libcamera signals both Camera::disconnected and CameraManager::cameraRemoved: count the loss once.
  if (streaming_.exchange(false)) bump(counters_.disconnects);
  restart_wanted_.store(true);
  supervisor_wake_.post();
  frame_ready_.post();
}

// ---- capture thread ----

SourceStatus LibcameraSource::next(FrameSlot& slot, const std::atomic<bool>& stop) noexcept {
  const std::int64_t start_ns = mono_now_ns();
  if (last_frame_ns_ < 0) last_frame_ns_ = start_ns;
  // A reloaded [exposure] max_us: the capture thread is the only writer of
  // the controls, so the new limit is applied here rather than by the main thread.
  if (const double max_us = exposure_max_us_.load(std::memory_order_relaxed); max_us != applied_exposure_max_us_) {
    apply_exposure(max_us);
  }
  const auto deadline_ns = start_ns + static_cast<std::int64_t>(settings_.stall_periods * static_cast<double>(period_ns_));
  for (;;) {
    if (stop.load(std::memory_order_relaxed)) return SourceStatus::stopped;
    if (const Completed* c = completed_.take_oldest(); c != nullptr) {
      // Announce the read, then check the stream is still mapped (both
      // sequentially consistent, against the supervisor's retire_stream():
      // either it sees the read and waits, or this sees the new generation).
      copying_.store(true);
      if (c->generation != generation_.load()) {
        copying_.store(false, std::memory_order_release);
        completed_.release();
        bump(counters_.stale_frames);
        continue;
      }
      deliver(*c, slot);
      if (Copied* back = copied_.try_claim(); back != nullptr) {
        back->buffer_index = c->buffer_index;
        back->generation = c->generation;
        copied_.publish();
      }  // never full: it has room for every buffer of two streams
      copying_.store(false, std::memory_order_release);
      completed_.release();
      supervisor_wake_.post();
      last_frame_ns_ = mono_now_ns();
      return SourceStatus::frame;
    }
    const std::int64_t now = mono_now_ns();
    if (now >= deadline_ns) {
      bump(counters_.frame_timeouts);
      const auto restart_ns = static_cast<std::int64_t>(settings_.retry_interval_ms * 1e6);
      const std::int64_t since_ns = std::max(last_frame_ns_, stream_started_ns_.load());
      if (streaming_.load() && now - since_ns >= restart_ns && !restart_wanted_.load()) {
        restart_wanted_.store(true);  // silent but not gone: the supervisor restarts it
        supervisor_wake_.post();
        last_frame_ns_ = now;
      }
      return SourceStatus::error;
    }
    frame_ready_.wait_for(std::min<std::int64_t>(deadline_ns - now, 20 * kNsPerMs));
  }
}

void LibcameraSource::deliver(const Completed& c, FrameSlot& slot) noexcept {
  // The one copy of the pixels: the camera's luma rows (stride-aware) into the slot.
  const auto width = static_cast<std::size_t>(settings_.camera.width_px);
  for (int row = 0; row < settings_.camera.height_px; ++row) {
    std::memcpy(slot.view.gray.ptr(row), c.luma + static_cast<std::size_t>(row) * c.stride_bytes, width);
  }
  bump(counters_.frames_copied);
  slot.view.index = c.index;
  slot.view.t_ns = c.t_ns;
  slot.view.exposure = core::ExposurePlan{};  // continuous light for the applied time (no strobe sync)
  slot.view.exposure.exposure_us = c.exposure_us;
  slot.defect = c.defect;
  slot.truth = FrameTruth{};
}

// ---- supervisor thread (not real-time): re-queue, re-open on a backoff ----

void LibcameraSource::requeue_copied() noexcept {
  while (const Copied* back = copied_.take_oldest()) {
    const Copied b = *back;
    copied_.release();
    // Only this thread changes the generation: a buffer of a retired stream is gone with it.
    if (b.generation != generation_.load(std::memory_order_relaxed)) continue;
    requeue(b.buffer_index);
    held_.fetch_sub(1, std::memory_order_acq_rel);  // after the queue: at least one request stays in the camera
  }
}

void LibcameraSource::retire_stream() noexcept {
  streaming_.store(false);
  generation_.fetch_add(1);  // from now on next() leaves this stream's buffers unread
  device_->stop();           // the camera thread's last callbacks return before this does
  while (copying_.load()) std::this_thread::sleep_for(std::chrono::microseconds(50));  // a copy in progress
  requeue_copied();          // drops what the capture thread gave back from the retired stream
  device_->close();          // unmaps its buffers
}

void LibcameraSource::supervise() noexcept {
  const auto retry_ns = static_cast<std::int64_t>(settings_.retry_interval_ms * 1e6);
  while (!quit_.load()) {
    supervisor_wake_.wait_for(100 * kNsPerMs);
    requeue_copied();
    if (quit_.load() || !restart_wanted_.load()) continue;
    retire_stream();
    while (!quit_.load()) {
      restart_wanted_.store(false);
      try {
        open_and_start();
        bump(counters_.restarts);
        const std::lock_guard<std::mutex> lock(error_mutex_);
        last_error_.clear();
        break;
      } catch (const std::exception& e) {
        {
          const std::lock_guard<std::mutex> lock(error_mutex_);
          last_error_ = e.what();
        }
        retire_stream();  // start() may have delivered frames before it failed
        // Wait out the backoff; wake-ups from frames copied meanwhile only drain their buffers.
        const std::int64_t until_ns = mono_now_ns() + retry_ns;
        for (std::int64_t now = mono_now_ns(); now < until_ns && !quit_.load(); now = mono_now_ns()) {
          supervisor_wake_.wait_for(until_ns - now);
          requeue_copied();
        }
      }
    }
  }
}

CameraHealth LibcameraSource::health() const noexcept {
  constexpr auto r = std::memory_order_relaxed;
  CameraHealth h;
  h.frames_delivered = counters_.frames_delivered.load(r);
  h.frames_copied = counters_.frames_copied.load(r);
  h.stale_frames = counters_.stale_frames.load(r);
  h.requests_cancelled = counters_.requests_cancelled.load(r);
  h.requests_incomplete = counters_.requests_incomplete.load(r);
  h.sequence_gaps = counters_.sequence_gaps.load(r);
  h.timestamps_backwards = counters_.timestamps_backwards.load(r);
  h.no_exposure_metadata = counters_.no_exposure_metadata.load(r);
  h.handoff_full = counters_.handoff_full.load(r);
  h.requeue_failures = counters_.requeue_failures.load(r);
  h.disconnects = counters_.disconnects.load(r);
  h.frame_timeouts = counters_.frame_timeouts.load(r);
  h.restarts = counters_.restarts.load(r);
  h.streaming = streaming_.load(r);
  return h;
}

std::string LibcameraSource::health_text() const {
  const CameraHealth h = health();
  std::ostringstream s;
  s << "camera " << camera_id_ << (h.streaming ? " streaming" : " DOWN") << ": delivered " << h.frames_delivered
    << ", copied " << h.frames_copied << ", stale " << h.stale_frames << ", cancelled " << h.requests_cancelled << ", incomplete " << h.requests_incomplete << ", sequence gaps "
    << h.sequence_gaps << ", time backwards " << h.timestamps_backwards << ", no exposure metadata "
    << h.no_exposure_metadata << ", hand-off full " << h.handoff_full << ", requeue failures "
    << h.requeue_failures << ", timeouts " << h.frame_timeouts << ", disconnects " << h.disconnects
    << ", restarts " << h.restarts;
  const std::lock_guard<std::mutex> lock(error_mutex_);
  if (!last_error_.empty()) s << ", last error: " << last_error_;
  return s.str();
}

}  // namespace gvs::drivers
