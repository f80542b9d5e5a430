// `libcamera[:ID]` frame source: a camera behind the CameraDevice seam
// (gvs/drivers/camera_device.hpp), libcamera 0.0.3 on the car, a fake in
// the tests. Each frame's pixels are copied once, by the capture thread:
//
//   camera thread   request completed: hands the request (buffer index,
//                   metadata, pointer to the mapped luma plane) to the
//                   capture thread through a lock-free ring; no pixel copy.
//   capture thread  next(): copies the luma rows from the camera's buffer
//                   straight into the frame ring's slot, then hands the
//                   buffer index to the supervisor.
//   supervisor      re-queues the copied buffer's request (libcamera's
//                   queueRequest allocates: never on the capture thread),
//                   and re-opens the camera on a backoff when it disappears
//                   or stops delivering.
//
// A buffer goes back to the camera only after the copy. The capture side
// holds at most buffers - 1 of them, so one request always stays queued;
// a frame completing while it holds that many is re-queued at once unread
// (counted: hand-off full). Before the supervisor stops and unmaps a stream
// it retires the stream's generation and waits for a copy in progress to
// end; requests of a retired generation still waiting are dropped unread.
#pragma once

#include <atomic>
#include <cstdint>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "gvs/drivers/frame_source.hpp"
#include "gvs/drivers/spsc_ring.hpp"
#include "gvs/drivers/wakeup.hpp"
#include "gvs/drivers/camera_device.hpp"

namespace gvs::drivers {

/// The source's settings (gvsd: [camera], [exposure] and [libcamera] of gvsd.toml).
struct LibcameraSettings {
  std::string camera_id;  ///< empty: the first camera the library lists
  core::CameraGeometry camera;
  double fps = 60.0;
  CameraPixelFormat pixel_format = CameraPixelFormat::yuv420;
  int buffer_count = 4;
  double exposure_initial_us = 3000.0;
  double exposure_min_us = 10.0;    ///< shortest ExposureTime sent
  double exposure_max_us = 3000.0;  ///< longest ExposureTime sent (also capped by the frame period); at start, then set_exposure_max_us
  double gain_min = 1.0;            ///< AnalogueGain at exposure_max_us
  double gain_max = 8.0;            ///< AnalogueGain never above this
  double stall_periods = 3.0;       ///< next() reports an error after this many periods without a frame
  double retry_interval_ms = 500.0; ///< re-open backoff; also how long a silent camera may stall before a restart
};

/// Picks the camera: `wanted` empty = the first of `ids`. Throws
/// std::runtime_error naming the cameras present and what to do.
std::string choose_camera(const std::vector<std::string>& ids, const std::string& wanted);

/// Controls for an exposure plan: ExposureTime clamped to
/// [exposure_min_us, min(exposure_max_us, 0.9 frame period)]; AnalogueGain
/// makes up for the shorter exposure (gain_min * exposure_max_us / exposure,
/// the image brightness stays put) within [gain_min, gain_max];
/// FrameDurationLimits fixed at 1/fps.
CameraControls camera_controls_for(const core::ExposurePlan& plan, const LibcameraSettings& s);
/// The same with `exposure_max_us` in place of s.exposure_max_us (a reloaded value).
CameraControls camera_controls_for(const core::ExposurePlan& plan, const LibcameraSettings& s,
                                            double exposure_max_us);

/// The source's counters (each written by one thread).
struct CameraHealth {
  std::uint64_t frames_delivered = 0;    ///< frames handed to the capture thread
  std::uint64_t frames_copied = 0;       ///< frames next() copied out of the camera's buffers (one copy each)
  std::uint64_t stale_frames = 0;        ///< handed over, then dropped unread: the camera was restarted first
  std::uint64_t requests_cancelled = 0;  ///< Request::RequestCancelled
  std::uint64_t requests_incomplete = 0; ///< buffer not FrameSuccess, or fewer bytes than a frame
  std::uint64_t sequence_gaps = 0;       ///< frames the sensor counted that never arrived
  std::uint64_t timestamps_backwards = 0;///< SensorTimestamp not after the previous one
  std::uint64_t no_exposure_metadata = 0;///< completed without ExposureTime in the metadata
  std::uint64_t handoff_full = 0;        ///< frames re-queued unread: the capture thread held buffers - 1
  std::uint64_t requeue_failures = 0;
  std::uint64_t disconnects = 0;         ///< camera gone (disconnected / cameraRemoved)
  std::uint64_t frame_timeouts = 0;      ///< next() errors: no frame within stall_periods
  std::uint64_t restarts = 0;            ///< successful re-opens after a fault
  bool streaming = false;
};

class LibcameraSource final : public FrameSource, private CameraEvents {
 public:
  /// Chooses, opens, configures and starts the camera. Throws
  /// std::runtime_error (no camera, unknown id, mode not available).
  LibcameraSource(std::unique_ptr<CameraDevice> device, const LibcameraSettings& settings);
  /// Stops and closes the camera. Not while next() runs (the capture thread
  /// has been joined).
  ~LibcameraSource() override;

  [[nodiscard]] std::string describe() const override;
  [[nodiscard]] core::CameraGeometry geometry() const override { return settings_.camera; }
  [[nodiscard]] double nominal_fps() const override { return settings_.fps; }
  void prepare(FrameSlot& slot) override;
  SourceStatus next(FrameSlot& slot, const std::atomic<bool>& stop) noexcept override;
  void set_exposure(const core::ExposurePlan& plan) noexcept override;
  [[nodiscard]] bool controls_exposure() const override { return true; }
  /// Takes effect from the next frame the capture thread asks for, with the
  /// last plan re-clamped (a fixed exposure gets no new plan to carry it).
  void set_exposure_max_us(double exposure_max_us) noexcept override;
  [[nodiscard]] bool frames_carry_light() const override { return false; }
  [[nodiscard]] std::string health_text() const override;

  [[nodiscard]] CameraHealth health() const noexcept;
  [[nodiscard]] const std::string& camera_id() const noexcept { return camera_id_; }

 private:
  /// A completed request on its way to the capture thread: the pixels
  /// stay in the camera's mapped buffer until next() copies them.
  struct Completed {
    std::uint32_t buffer_index = 0;
    std::uint32_t generation = 0;  ///< the stream it came from
    const std::uint8_t* luma = nullptr;
    std::size_t stride_bytes = 0;
    std::int64_t index = 0;
    std::int64_t t_ns = 0;
    double exposure_us = 0.0;
    std::optional<core::RejectReason> defect;
  };
  /// A buffer next() has copied, on its way back to the camera.
  struct Copied {
    std::uint32_t buffer_index = 0;
    std::uint32_t generation = 0;
  };

  // camera library's thread
  void request_completed(const CompletedRequest& done) noexcept override;
  void camera_disconnected() noexcept override;
  CameraControls current_controls() const noexcept;
  void apply_exposure(double exposure_max_us) noexcept;  // capture thread

  void requeue(std::uint32_t buffer_index) noexcept;  // camera thread or supervisor
  void deliver(const Completed& c, FrameSlot& slot) noexcept;  // capture thread

  // supervisor (and the constructor / destructor)
  void open_and_start();  // throws
  void retire_stream() noexcept;
  void requeue_copied() noexcept;
  void supervise() noexcept;

  std::unique_ptr<CameraDevice> device_;
  LibcameraSettings settings_;
  std::string camera_id_;
  std::int64_t period_ns_ = 0;

  SpscRing<Completed> completed_;  ///< camera thread -> capture thread
  SpscRing<Copied> copied_;        ///< capture thread -> supervisor
  /// The stream whose buffers may be read; the supervisor advances it before
  /// it stops and unmaps a stream.
  std::atomic<std::uint32_t> generation_{0};
  std::atomic<bool> copying_{false};  ///< next() is reading a camera buffer
  std::atomic<int> held_{0};          ///< buffers handed over and not yet re-queued
  Wakeup frame_ready_;
  Wakeup supervisor_wake_;
  std::atomic<std::uint64_t> controls_packed_{0};  ///< exposure_us (low 32) | gain float bits (high 32)
  static_assert(std::atomic<double>::is_always_lock_free, "exposure_max_us_ is read on the capture thread");
  std::atomic<double> exposure_max_us_{0.0};  ///< written by the main thread (reload)

  // camera thread state (set before each start)
  std::uint32_t stream_generation_ = 0;
  int max_held_ = 1;  ///< buffers - 1
  bool new_stream_ = true;
  std::int64_t index_base_ = 0;
  std::int64_t last_index_ = -1;
  std::uint32_t last_sequence_ = 0;
  std::int64_t last_t_ns_ = -1;

  // capture thread state
  std::int64_t last_frame_ns_ = -1;
  core::ExposurePlan plan_;            ///< the last plan asked for
  double applied_exposure_max_us_ = 0.0;  ///< the limit controls_packed_ was clamped with

  std::atomic<bool> streaming_{false};
  std::atomic<std::int64_t> stream_started_ns_{0};  ///< monotonic time of the last start (supervisor)
  std::atomic<bool> restart_wanted_{false};
  std::atomic<bool> quit_{false};
  mutable std::mutex error_mutex_;  ///< supervisor and main thread only
  std::string last_error_;

  struct Counters {
    std::atomic<std::uint64_t> frames_delivered{0}, frames_copied{0}, stale_frames{0}, requests_cancelled{0},
        requests_incomplete{0}, sequence_gaps{0}, timestamps_backwards{0}, no_exposure_metadata{0}, handoff_full{0},
        requeue_failures{0}, disconnects{0}, frame_timeouts{0}, restarts{0};
  } counters_;
  std::thread supervisor_;
};

}  // namespace gvs::drivers
