// gvs record: a gvs-dataset/1 from a live source (shared/spec/dataset-format.md),
// so a run on the car can be replayed and evaluated on a desk.
//   gvs record --out DIR [--seconds S] [--config gvsd.toml] [--source URI]
// Each frame is written with the exposure the camera actually applied (the
// libcamera source takes it from the request's metadata) and its start-of-
// exposure time; frames the source could not deliver whole are left out and
// show as index gaps. The exposure stays at [exposure] initial_us (no closed
// loop while recording). A simulated source (sim:) also writes truth.csv, so
// the recorder itself can be checked with gvs replay + gvs eval.
#include <condition_variable>
#include <cstdio>
#include <deque>
#include <mutex>
#include <thread>
#include <vector>
#include <filesystem>
#include <memory>
#include <stdexcept>
#include <string>

#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include "commands.hpp"
#include "usage.hpp"
#include "gvs/drivers/clock.hpp"
#include "gvs/drivers/dataset.hpp"
#include "gvs/core/frame.hpp"
#include "live_source.hpp"

namespace gvs::cli {

namespace {

struct RecordOptions {
  std::string out;
  double seconds = 10.0;
  std::string config_file;
  std::string source_uri;
};

/// A frame waiting for the disk.
struct PendingFrame {
  cv::Mat gray;  ///< from the pool, allocated once
  drivers::FrameRecord record;
  drivers::FrameTruth truth;
};

/// Writes frames on its own thread, so PNG encoding never holds up the
/// camera; when the disk falls behind by the whole pool, frames are left
/// out (index gaps) and counted.
class BackgroundWriter {
 public:
  BackgroundWriter(drivers::DatasetWriter& writer, bool with_truth, const core::CameraGeometry& g, std::size_t pool)
      : writer_(writer), with_truth_(with_truth) {
    for (std::size_t i = 0; i < pool; ++i) free_.push_back(cv::Mat(g.height_px, g.width_px, CV_8UC1));
    thread_ = std::thread([this] { run(); });
  }
  ~BackgroundWriter() { stop_thread(); }
  BackgroundWriter(const BackgroundWriter&) = delete;
  BackgroundWriter& operator=(const BackgroundWriter&) = delete;

  /// False when the pool is exhausted (the frame is left out).
  bool push(const drivers::FrameSlot& slot, const drivers::FrameRecord& rec) {
    std::unique_lock<std::mutex> lock(mutex_);
    if (free_.empty()) return false;
    PendingFrame f{free_.back(), rec, slot.truth};
    free_.pop_back();
    lock.unlock();
    slot.view.gray.copyTo(f.gray);
    lock.lock();
    queue_.push_back(std::move(f));
    cv_.notify_one();
    return true;
  }
  /// Writes what is queued, stops the thread; throws the first write error.
  void finish() {
    stop_thread();
    if (!error_.empty()) throw std::runtime_error(error_);
  }
  [[nodiscard]] long written() const { return written_; }

 private:
  void run() {
    for (;;) {
      std::unique_lock<std::mutex> lock(mutex_);
      cv_.wait(lock, [this] { return done_ || !queue_.empty(); });
      if (queue_.empty()) return;
      PendingFrame f = std::move(queue_.front());
      queue_.pop_front();
      lock.unlock();
      try {
        if (error_.empty()) write(f);
      } catch (const std::exception& e) {
        error_ = e.what();
      }
      lock.lock();
      free_.push_back(f.gray);
    }
  }
  void stop_thread() noexcept {
    {
      const std::lock_guard<std::mutex> lock(mutex_);
      done_ = true;
    }
    cv_.notify_one();
    if (thread_.joinable()) thread_.join();
  }
  void write(const PendingFrame& f) {
    writer_.write_frame(f.gray, f.record);
    ++written_;
    if (!with_truth_ || !f.truth.known) return;
    drivers::TruthRecord truth;
    truth.index = f.record.index;
    truth.t_ns = core::mid_exposure_ns(f.record.t_ns, f.record.exposure);
    truth.vx_mps = f.truth.vx_mps;
    truth.vy_mps = f.truth.vy_mps;
    truth.speed_mps = f.truth.speed_mps;
    if (f.truth.speed_mps >= 0.01) truth.direction_deg = f.truth.direction_deg;
    truth.yaw_rate_dps = f.truth.yaw_rate_dps;
    writer_.write_truth(truth);
  }

  drivers::DatasetWriter& writer_;
  bool with_truth_;
  std::mutex mutex_;
  std::condition_variable cv_;
  std::vector<cv::Mat> free_;
  std::deque<PendingFrame> queue_;
  bool done_ = false;
  std::string error_;  ///< written by the writer thread, read after join
  long written_ = 0;   ///< likewise
  std::thread thread_;
};

void run_record(const RecordOptions& o) {
  if (std::filesystem::exists(o.out) && !std::filesystem::is_empty(o.out)) {
    throw std::runtime_error(o.out + ": exists and is not empty; name a new folder for the recording");
  }
  LiveSource live = open_live_source(o.config_file, o.source_uri);
  drivers::CameraInfo camera;
  camera.geometry = live.source->geometry();
  camera.description = "gvs record from " + live.source->describe();
  const bool simulated = live.config.source_uri.rfind("sim:", 0) == 0;  // the simulator knows its truth
  drivers::DatasetWriter writer(o.out, camera, simulated);
  std::fprintf(stderr, "recording %s for %.1f s into %s (Ctrl-C stops)\n", live.source->describe().c_str(),
               o.seconds, o.out.c_str());
  install_stop_signals();

  long delivered = 0, defects = 0, errors = 0, disk_behind = 0;
  {
    BackgroundWriter background(writer, simulated, camera.geometry, 120);
    const std::int64_t end_ns = drivers::mono_now_ns() + static_cast<std::int64_t>(o.seconds * 1e9);
    std::int64_t first_index = -1;
    std::atomic<bool>& stop = stop_requested();
    while (drivers::mono_now_ns() < end_ns && !stop.load()) {
      const drivers::SourceStatus st = live.source->next(live.slot, stop);
      if (st == drivers::SourceStatus::stopped || st == drivers::SourceStatus::end) break;
      if (st == drivers::SourceStatus::error) {
        ++errors;
        continue;
      }
      if (live.slot.defect) {  // no pixels or no trustworthy exposure: a gap, not a guess
        ++defects;
        continue;
      }
      ++delivered;
      if (first_index < 0) first_index = live.slot.view.index;
      drivers::FrameRecord rec;
      rec.index = live.slot.view.index - first_index;
      rec.t_ns = live.slot.view.t_ns;
      rec.exposure = live.slot.view.exposure;  // the applied exposure (libcamera: request metadata)
      if (!background.push(live.slot, rec)) ++disk_behind;
    }
    background.finish();
    writer.close();
    const std::string health = live.source->health_text();
    std::printf("recorded %ld frames into %s (%ld delivered; left out: %ld defective, %ld with the disk behind; "
                "%ld source errors)%s%s\n",
                background.written(), o.out.c_str(), delivered, defects, disk_behind, errors,
                health.empty() ? "" : "\n", health.c_str());
    if (background.written() == 0) throw std::runtime_error("no frame recorded from " + live.source->describe());
  }
}

}  // namespace

void register_record(CLI::App& app) {
  auto opts = std::make_shared<RecordOptions>();
  CLI::App* cmd = app.add_subcommand("record", "Record a gvs-dataset from the live camera (applied exposure, timestamps)");
  cmd->add_option("--out", opts->out, "Dataset folder to create")->required();
  cmd->add_option("--seconds", opts->seconds, "How long to record")->capture_default_str()->check(number_in(0.01, 86400.0));
  cmd->add_option("--config", opts->config_file, "gvsd configuration (TOML): source, camera, [libcamera], exposure")
      ->check(CLI::ExistingFile);
  cmd->add_option("--source", opts->source_uri, "Source URI, overrides the configuration: libcamera[:ID], sim:SCENARIO");
  cmd->callback([opts] { run_record(*opts); });
}

}  // namespace gvs::cli
