// A camera at the CameraDevice seam that behaves like libcamera 0.0.3 where
// the source depends on it: completions on the camera's own thread, one
// reusable request per buffer, frames only for queued requests (a frame
// without a queued buffer is lost and its sequence number skipped), pending
// requests completed as cancelled by stop(), controls applied as the sensor
// can (exposure rounded to whole 14 us lines, so applied != asked), a
// disconnect signal when unplugged. Tests script faults through FakeCamera.
// A completed buffer is the application's until it is queued again: queue()
// overwrites it at once (0xEE, as the next DMA would) and close() frees it,
// so a source reading a buffer after giving it back reads 0xEE (and races,
// for TSan), and one reading it after close reads freed memory (ASan).
#pragma once

#include <algorithm>
#include <atomic>
#include <cmath>
#include <deque>
#include <map>
#include <mutex>
#include <stdexcept>
#include <thread>
#include <vector>

#include "gvs/drivers/clock.hpp"
#include "gvs/drivers/camera_device.hpp"

namespace gvs::drivers::testing {

/// The camera's world, shared by the test and the device.
struct FakeCamera {
  static constexpr double kLineUs = 14.0;  ///< the sensor's exposure step

  std::vector<std::string> ids{"/base/fake/imx296@1a"};
  double fps = 50.0;
  int stride_padding = 16;         ///< bytes after each row (stride > width)

  std::atomic<bool> present{true};  ///< unplugged: open fails, frames stop, disconnect signalled
  std::atomic<bool> stalled{false}; ///< present but silent
  // one-shot faults for the next completed frame
  std::atomic<int> skip_sequences{0};
  std::atomic<bool> timestamp_backwards{false};
  std::atomic<bool> omit_exposure{false};
  std::atomic<bool> buffer_error{false};

  // what the device saw
  std::atomic<int> opens{0};
  std::atomic<int> starts{0};
  std::atomic<std::uint64_t> queued{0};  ///< requests queued (first queue and re-queues)
  std::atomic<int> with_app{0};          ///< buffers completed and not yet queued again
  std::mutex seen_mutex;
  std::map<std::uint32_t, int> queue_count_by_buffer;
  CameraControls last_controls;
  CameraStreamRequest last_request;

  CameraControls seen_controls() {
    const std::lock_guard<std::mutex> lock(seen_mutex);
    return last_controls;
  }
  std::map<std::uint32_t, int> seen_buffers() {
    const std::lock_guard<std::mutex> lock(seen_mutex);
    return queue_count_by_buffer;
  }
  static std::int32_t applied_exposure_us(std::int32_t asked_us) {
    return static_cast<std::int32_t>(std::max(1.0, std::floor(asked_us / kLineUs)) * kLineUs);
  }
};

class FakeCameraDevice final : public CameraDevice {
 public:
  explicit FakeCameraDevice(std::shared_ptr<FakeCamera> world) : w_(std::move(world)) {}
  ~FakeCameraDevice() override { close(); }

  std::string describe() const override { return "fake camera"; }
  std::vector<std::string> list_cameras() override {
    return w_->present.load() ? w_->ids : std::vector<std::string>{};
  }
  void open(const std::string& id) override {
    if (!w_->present.load() || std::find(w_->ids.begin(), w_->ids.end(), id) == w_->ids.end()) {
      throw std::runtime_error("fake: camera '" + id + "' is not present");
    }
    ++w_->opens;
    open_ = true;
  }
  CameraStreamInfo configure(const CameraStreamRequest& r) override {
    if (!open_) throw std::runtime_error("fake: configure before open");
    request_ = r;
    {
      const std::lock_guard<std::mutex> lock(w_->seen_mutex);
      w_->last_request = r;
    }
    stride_ = static_cast<std::size_t>(r.width_px + w_->stride_padding);
    buffers_.assign(static_cast<std::size_t>(r.buffer_count),
                    std::vector<std::uint8_t>(stride_ * static_cast<std::size_t>(r.height_px), 0xEE));
    with_app_.assign(buffers_.size(), false);
    return {r.width_px, r.height_px, stride_, r.buffer_count};
  }
  void start(const CameraControls& controls, CameraEvents& events) override {
    if (!w_->present.load()) throw std::runtime_error("fake: camera gone");
    events_ = &events;
    stopping_.store(false);
    pending_.clear();
    for (std::uint32_t i = 0; i < buffers_.size(); ++i) queue(i, controls);
    ++w_->starts;
    thread_ = std::thread([this] { run(); });
  }
  bool queue(std::uint32_t index, const CameraControls& controls) noexcept override {
    if (stopping_.load() || !w_->present.load() || index >= buffers_.size()) return false;
    std::fill(buffers_[index].begin(), buffers_[index].end(), std::uint8_t{0xEE});
    {
      const std::lock_guard<std::mutex> lock(mutex_);
      if (with_app_[index]) --w_->with_app;
      with_app_[index] = false;
      pending_.push_back({index, controls});
    }
    ++w_->queued;
    const std::lock_guard<std::mutex> lock(w_->seen_mutex);
    ++w_->queue_count_by_buffer[index];
    w_->last_controls = controls;
    return true;
  }
  void stop() noexcept override {
    stopping_.store(true);
    if (thread_.joinable()) thread_.join();
    std::deque<Pending> left;
    {
      const std::lock_guard<std::mutex> lock(mutex_);
      left.swap(pending_);
    }
    for (const Pending& p : left) {  // as libcamera: pending requests complete cancelled
      CompletedRequest done;
      done.buffer_index = p.index;
      done.cancelled = true;
      if (events_ != nullptr) events_->request_completed(done);
    }
    events_ = nullptr;
  }
  void close() noexcept override {
    stop();
    buffers_.clear();  // "unmapped": a later read is a use-after-free
    buffers_.shrink_to_fit();
    w_->with_app = 0;
    open_ = false;
  }

 private:
  struct Pending {
    std::uint32_t index;
    CameraControls controls;
  };

  void run() {
    const auto period_ns = static_cast<std::int64_t>(1e9 / w_->fps);
    std::int64_t next_ns = mono_now_ns() + period_ns;
    std::uint32_t sequence = 0;
    bool told_gone = false;
    std::int64_t last_t_ns = 0;
    while (!stopping_.load()) {
      sleep_until_ns(next_ns);
      next_ns += period_ns;
      if (!w_->present.load()) {
        if (!told_gone) events_->camera_disconnected();
        told_gone = true;
        continue;
      }
      if (w_->stalled.load()) continue;
      sequence += static_cast<std::uint32_t>(w_->skip_sequences.exchange(0));
      Pending p{};
      {
        const std::lock_guard<std::mutex> lock(mutex_);
        if (pending_.empty()) {
          ++sequence;  // no buffer queued: the frame is lost
          continue;
        }
        p = pending_.front();
        pending_.pop_front();
        with_app_[p.index] = true;
        ++w_->with_app;
      }
      std::vector<std::uint8_t>& buf = buffers_[p.index];
      for (int y = 0; y < request_.height_px; ++y) {
        for (int x = 0; x < request_.width_px; ++x) {
          buf[static_cast<std::size_t>(y) * stride_ + static_cast<std::size_t>(x)] =
              static_cast<std::uint8_t>((x + 3 * y + static_cast<int>(sequence)) & 0x7F);
        }
      }
      CompletedRequest done;
      done.buffer_index = p.index;
      done.sequence = sequence++;
      const std::int32_t applied = FakeCamera::applied_exposure_us(p.controls.exposure_us);
      done.exposure_us = w_->omit_exposure.exchange(false) ? -1 : applied;
      done.analogue_gain = p.controls.analogue_gain;
      std::int64_t t = mono_now_ns() - static_cast<std::int64_t>(applied) * 1000;
      if (w_->timestamp_backwards.exchange(false)) t = last_t_ns - 5 * kNsPerMs;
      last_t_ns = std::max(last_t_ns, t);
      done.sensor_timestamp_ns = t;
      done.buffer_ok = !w_->buffer_error.exchange(false);
      done.luma = buf.data();
      done.stride_bytes = stride_;
      done.bytes_used = buf.size();
      events_->request_completed(done);
    }
  }

  std::shared_ptr<FakeCamera> w_;
  bool open_ = false;
  CameraStreamRequest request_;
  std::size_t stride_ = 0;
  std::vector<std::vector<std::uint8_t>> buffers_;
  std::vector<bool> with_app_;  ///< guarded by mutex_
  CameraEvents* events_ = nullptr;
  std::mutex mutex_;
  std::deque<Pending> pending_;
  std::atomic<bool> stopping_{false};
  std::thread thread_;
};

}  // namespace gvs::drivers::testing
