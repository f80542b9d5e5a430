// The three real-time threads and what they share:
//   capture --SpscRing<FrameSlot>--> processing --Seqlock<PublishedEstimate>--> CAN sender
//   processing --Seqlock<ExposurePlan>--> capture (closed-loop exposure)
// Everything is allocated in the constructor and start(); the loops only
// touch preallocated memory and atomics, and report through HealthCounters.
#pragma once

#include <array>
#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <thread>
#include <vector>

#include "gvs/can/codec.hpp"
#include "gvs/can/height_receiver.hpp"
#include "gvs/can/sink.hpp"
#include "gvs/daemon/config.hpp"
#include "gvs/daemon/frame_estimator.hpp"
#include "gvs/drivers/frame_slot.hpp"
#include "gvs/drivers/frame_source.hpp"
#include "gvs/daemon/health_counters.hpp"
#include "gvs/daemon/plausibility_gate.hpp"
#include "gvs/daemon/published_estimate.hpp"
#include "gvs/daemon/rt.hpp"
#include "gvs/daemon/seqlock.hpp"
#include "gvs/daemon/slot_phase_lock.hpp"
#include "gvs/daemon/warm_up.hpp"
#include "gvs/drivers/spsc_ring.hpp"
#include "gvs/drivers/wakeup.hpp"
#include "gvs/drivers/strobe.hpp"
#include "gvs/dsp/exposure_control.hpp"

namespace gvs::daemon {

enum class ThreadRole : int { capture = 0, processing = 1, sender = 2 };
inline constexpr std::size_t kThreadCount = 3;
const char* role_name(ThreadRole role);

/// Per-send timing, recorded by the sender into preallocated arrays (benchmark).
struct SenderRecords {
  std::vector<std::int64_t> wakeup_late_ns;    ///< actual wake-up - scheduled, per tick
  std::vector<std::int64_t> frame_to_can_ns;   ///< send done - frame received by capture, per new estimate
  std::vector<std::int64_t> frame_to_publish_ns;///< estimate published - frame received, per new estimate
  std::size_t wakeups = 0;
  std::size_t estimates = 0;
};

/// Hooks for tests and benchmarks (all optional).
struct PipelineHooks {
  /// Called on each RT thread right before it enters its loop (after its setup).
  std::function<void(ThreadRole)> on_loop_start;
  /// When > 0, the sender records this many timing samples (see records()).
  std::size_t record_capacity = 0;
  /// When > 0, the sender stops after this many periods and run_complete()
  /// turns true (--run-for): a bounded run sends exactly that many frames.
  std::uint64_t max_ticks = 0;
  /// When set, builds the [light] driver instead of drivers::make_strobe_driver
  /// (tests: a strobe whose failures they script).
  std::function<std::unique_ptr<drivers::StrobeDriver>(const drivers::StrobeConfig&)> make_light;
  /// With [height] source = "can": called on the processing thread before
  /// each estimate instead of reading the CAN interface, to add the samples
  /// received since (tests: a distance sensor they script).
  std::function<void(can::HeightHistory&)> height_samples;
};

/// Progress counters for the watchdog: each changes while its thread runs.
struct Progress {
  std::array<std::uint64_t, kThreadCount> beats{};
};

/// The systemd watchdog rule: feed (WATCHDOG=1) only when every thread's
/// heartbeat moved since the last feed. A thread that hangs keeps its count,
/// the feeding stops, and systemd kills and restarts gvsd after WatchdogSec.
class WatchdogGate {
 public:
  explicit WatchdogGate(const Progress& start) : last_(start) {}
  /// True when gvsd may feed the watchdog now (then `now` becomes the reference).
  bool should_feed(const Progress& now) {
    for (std::size_t i = 0; i < kThreadCount; ++i) {
      if (now.beats[i] == last_.beats[i]) return false;
    }
    last_ = now;
    return true;
  }

 private:
  Progress last_;
};

class Pipeline {
 public:
  Pipeline(const DaemonConfig& config, std::unique_ptr<drivers::FrameSource> source,
           std::unique_ptr<FrameEstimator> estimator, std::unique_ptr<can::CanSink> sink,
           PipelineHooks hooks = {});
  ~Pipeline();
  Pipeline(const Pipeline&) = delete;
  Pipeline& operator=(const Pipeline&) = delete;

  /// Prepares the ring, warms the estimator, starts the three threads and
  /// waits until each has done its real-time setup.
  void start();
  /// Asks every thread to stop (async-signal-safe: one atomic store).
  void request_stop() noexcept { stop_.store(true, std::memory_order_relaxed); }
  /// Waits for the threads. After request_stop() the sender sends a last
  /// status with state Stopping (not after a max_ticks run).
  void join();

  /// Settings a SIGHUP may change while running.
  void apply_reloadable(const DaemonConfig& config) noexcept;

  /// The sender has sent its max_ticks periods.
  [[nodiscard]] bool run_complete() const noexcept { return run_complete_.load(std::memory_order_acquire); }
  [[nodiscard]] bool source_ended() const noexcept { return source_ended_.load(std::memory_order_acquire); }
  [[nodiscard]] const HealthCounters& counters() const noexcept { return counters_; }
  [[nodiscard]] Progress progress() const noexcept;
  [[nodiscard]] PublishedEstimate latest() const noexcept { return latest_.read(); }
  [[nodiscard]] core::ExposurePlan requested_exposure() const noexcept { return exposure_request_.read(); }
  [[nodiscard]] const std::array<ThreadRtReport, kThreadCount>& rt_reports() const noexcept { return reports_; }
  [[nodiscard]] bool realtime() const noexcept;
  /// Valid after join().
  [[nodiscard]] const SenderRecords& records() const noexcept { return records_; }
  [[nodiscard]] const drivers::FrameSource& source() const noexcept { return *source_; }
  /// Main thread: the source's lines to log (FrameSource::take_log_lines).
  std::vector<std::string> take_source_log_lines() { return source_->take_log_lines(); }
  [[nodiscard]] std::string_view sink_description() const noexcept { return sink_->description(); }
  /// The [light] driver ("none" without one).
  [[nodiscard]] std::string light_description() const { return light_ ? light_->describe() : "none"; }
  /// Main thread: the next CAN sink event (interface down, bus-off, ...) the
  /// sender queued, oldest first; false when none is waiting.
  bool pop_sink_event(can::SinkEvent& out) noexcept;
  /// Sink events lost because the main thread did not collect them in time.
  [[nodiscard]] std::uint64_t sink_events_lost() const noexcept {
    return sink_events_lost_.load(std::memory_order_relaxed);
  }

 private:
  struct ExposureSettings {
    dsp::ExposureMode mode = dsp::ExposureMode::fixed;
    dsp::ExposureLimits limits;
  };

  void capture_loop() noexcept;
  void fire_light() noexcept;
  void stamp_light(drivers::FrameSlot& slot) noexcept;
  void processing_loop() noexcept;
  void sender_loop() noexcept;
  void run_thread(ThreadRole role, const ThreadConfig& config);
  void send_frame(const can::CanFrame& frame) noexcept;
  void collect_sink_events() noexcept;
  can::StatusMsg make_status(const PublishedEstimate& latest, const can::VelocityPair& sent) noexcept;

  DaemonConfig config_;
  std::unique_ptr<drivers::FrameSource> source_;
  std::unique_ptr<FrameEstimator> estimator_;
  std::unique_ptr<can::CanSink> sink_;
  std::unique_ptr<drivers::StrobeDriver> light_;  ///< [light]; fired by the capture thread
  /// The LED's latest on-intervals (measured edges), oldest first: the light
  /// stamped on frames of sources that do not carry it. Capture thread only.
  std::array<drivers::LitInterval, 16> lit_{};
  std::size_t lit_count_ = 0;
  PipelineHooks hooks_;

  drivers::SpscRing<drivers::FrameSlot> ring_;
  drivers::FrameSlot spare_;  ///< where the capture thread puts a frame the full ring has no room for
  std::optional<WarmUpFrames> warm_up_frames_;  ///< made by start(), used and freed by the processing thread
  drivers::Wakeup frame_ready_;
  Seqlock<PublishedEstimate> latest_;
  Seqlock<core::ExposurePlan> exposure_request_;
  Seqlock<ExposureSettings> exposure_settings_;  ///< written by the main thread (reload)
  Seqlock<PlausibilityLimits> plausibility_limits_;  ///< written by the main thread (reload)
  PlausibilityGate gate_;  ///< processing thread only
  std::optional<SlotPhaseLock> phase_lock_;  ///< sender thread only; [can] align_to_frames
  /// [height] source = "can": the distance sensor's frames (unless
  /// hooks_.height_samples stands in) and their history; processing thread only.
  std::unique_ptr<can::HeightReceiver> height_receiver_;
  can::HeightHistory height_history_;
  bool external_height_ = false;
  can::Encoder encoder_;

  std::atomic<std::int64_t> staleness_ms_{50};
  static_assert(std::atomic<double>::is_always_lock_free, "min_quality_ is read on the RT threads");
  std::atomic<double> min_quality_{0.3};  ///< [can] min_quality: read by the processing and sender threads
  std::atomic<std::int64_t> late_limit_ns_{1'000'000};
  std::atomic<bool> stop_{false};
  std::atomic<bool> source_ended_{false};
  std::atomic<bool> run_complete_{false};
  std::uint64_t max_ticks_ = 0;
  std::atomic<int> threads_ready_{0};
  HealthCounters counters_;
  std::array<ThreadRtReport, kThreadCount> reports_{};
  std::vector<std::thread> threads_;
  SenderRecords records_;
  drivers::SpscRing<can::SinkEvent> sink_events_;  ///< sender -> main thread (FIFO)
  std::atomic<std::uint64_t> sink_events_lost_{0};

  // Sender-thread state, kept between status messages.
  HealthSnapshot status_last_{};
  std::uint64_t last_frames_captured_ = 0;
};

}  // namespace gvs::daemon
