#include "gvs/drivers/replay_source.hpp"

#include <algorithm>
#include <chrono>
#include <sstream>
#include <stdexcept>
#include <unordered_map>

#include "gvs/drivers/clock.hpp"

namespace gvs::drivers {

namespace {

constexpr std::size_t kMinWindowFrames = 4;
/// How often a waiting thread looks again: the decoder when the window is
/// full, the capture thread when its frame is not decoded yet (rare: the
/// decoder is a window ahead).
constexpr std::int64_t kDecoderPollNs = 2 * kNsPerMs;
constexpr std::int64_t kCapturePollNs = kNsPerMs / 2;

void check_index(const std::filesystem::path& folder, const std::vector<FrameRecord>& records) {
  if (records.empty()) throw std::runtime_error(folder.string() + ": the dataset has no frames");
}

/// Frames per second from the index: frame index steps over time (0 if it cannot tell).
double dataset_fps(const std::vector<FrameRecord>& records) {
  if (records.size() < 2) return 0.0;
  const double span_s = static_cast<double>(records.back().t_ns - records.front().t_ns) / 1e9;
  const auto steps = static_cast<double>(records.back().index - records.front().index);
  return span_s > 0.0 && steps > 0.0 ? steps / span_s : 0.0;
}

}  // namespace

ReplaySource::Checked ReplaySource::check(const std::filesystem::path& folder) {
  try {
    const DatasetReader reader(folder);
    check_index(folder, reader.frames());
    return {reader.camera().geometry, dataset_fps(reader.frames())};
  } catch (const DatasetError& e) {
    throw std::runtime_error(std::string("replay: ") + e.what());
  }
}

ReplaySource::ReplaySource(const std::filesystem::path& folder, double window_mb) : folder_(folder) {
  try {
    reader_.emplace(folder);
    geometry_ = reader_->camera().geometry;
    records_ = reader_->frames();
    check_index(folder, records_);
    std::unordered_map<std::int64_t, const TruthRecord*> by_index;
    for (const auto& t : reader_->truth()) by_index[t.index] = &t;
    truth_.resize(records_.size());
    for (std::size_t i = 0; i < records_.size(); ++i) {
      auto it = by_index.find(records_[i].index);
      if (it == by_index.end()) continue;
      const TruthRecord& t = *it->second;
      truth_[i] = FrameTruth{true, t.vx_mps, t.vy_mps, t.speed_mps, t.direction_deg.value_or(0.0), t.yaw_rate_dps};
    }
    fps_ = dataset_fps(records_);
  } catch (const DatasetError& e) {
    throw std::runtime_error(std::string("replay: ") + e.what());
  }

  const double frame_mb = static_cast<double>(geometry_.width_px) * geometry_.height_px / 1048576.0;
  const auto fitting = static_cast<std::size_t>(std::max(0.0, window_mb / frame_mb));
  window_.resize(std::min(records_.size(), std::max(kMinWindowFrames, fitting)));
  for (Decoded& d : window_) d.gray.create(geometry_.height_px, geometry_.width_px, CV_8UC1);

  // The first window now, so playing starts with the decoder a window ahead.
  std::size_t good = 0;
  for (std::size_t i = 0; i < window_.size(); ++i) if (decode_into_window(i)) ++good;
  decoded_.store(window_.size(), std::memory_order_release);
  if (good == 0) {
    throw std::runtime_error(folder.string() + ": none of the first " + std::to_string(window_.size()) +
                             " frames of the dataset could be read");
  }
  if (window_.size() < records_.size()) decoder_ = std::thread([this] { decoder_loop(); });
}

ReplaySource::~ReplaySource() {
  quit_.store(true, std::memory_order_relaxed);
  if (decoder_.joinable()) decoder_.join();
}

bool ReplaySource::decode_into_window(std::size_t i) {
  // A frame that cannot be decoded or has the wrong size is kept as a
  // defect: it is delivered in its turn with no pixels, gets no estimate
  // (named unreadable / wrong-size) and is counted, like a camera frame
  // that arrives broken; the frames around it play normally.
  Decoded& d = window_[i % window_.size()];
  d.defect.reset();
  std::string problem;
  try {
    const cv::Mat gray = reader_->load_gray(i);
    if (gray.cols != geometry_.width_px || gray.rows != geometry_.height_px) {
      std::ostringstream msg;
      msg << records_[i].file << " is " << gray.cols << 'x' << gray.rows << " px but camera.json says "
          << geometry_.width_px << 'x' << geometry_.height_px;
      problem = msg.str();
      d.defect = core::RejectReason::wrong_size;
    } else {
      gray.copyTo(d.gray);  // same size and type: into the preallocated buffer
    }
  } catch (const DatasetError& e) {
    problem = e.what();
    d.defect = core::RejectReason::unreadable;
  }
  if (!d.defect) return true;
  const std::lock_guard<std::mutex> lock(log_mutex_);
  log_lines_.push_back("replay: frame " + std::to_string(records_[i].index) + " gets no estimate: " + problem);
  return false;
}

void ReplaySource::decoder_loop() noexcept {
  const std::size_t n = records_.size();
  for (std::size_t i = decoded_.load(std::memory_order_relaxed); i < n; ++i) {
    // Frame i takes the slot of frame i - window: wait until that one is copied out.
    while (i - consumed_.load(std::memory_order_acquire) >= window_.size()) {
      if (quit_.load(std::memory_order_relaxed)) return;
      sleep_until_ns(mono_now_ns() + kDecoderPollNs);
    }
    if (quit_.load(std::memory_order_relaxed)) return;
    try {
      (void)decode_into_window(i);
    } catch (...) {  // out of memory while decoding: the frame goes out as unreadable
      window_[i % window_.size()].defect = core::RejectReason::unreadable;
    }
    decoded_.store(i + 1, std::memory_order_release);
  }
}

std::string ReplaySource::describe() const {
  std::ostringstream s;
  s << "replay:" << folder_.string() << " (" << records_.size() << " frames, " << fps_ << " fps, "
    << geometry_.width_px << 'x' << geometry_.height_px << " px, " << window_.size() << " decoded ahead)";
  return s.str();
}

std::string ReplaySource::health_text() const {
  const std::uint64_t waited = waited_for_decoder_.load(std::memory_order_relaxed);
  if (waited == 0) return {};
  return "replay: " + std::to_string(waited) +
         " frames waited for the decoder (delivered late: it fell behind the dataset's pace)";
}

std::vector<std::string> ReplaySource::take_log_lines() {
  const std::lock_guard<std::mutex> lock(log_mutex_);
  std::vector<std::string> lines;
  lines.swap(log_lines_);
  return lines;
}

void ReplaySource::prepare(FrameSlot& slot) {
  slot.view.gray.create(geometry_.height_px, geometry_.width_px, CV_8UC1);
  slot.view.gray.setTo(0);
}

SourceStatus ReplaySource::next(FrameSlot& slot, const std::atomic<bool>& stop) noexcept {
  if (next_ >= records_.size()) return SourceStatus::end;
  const std::size_t i = next_++;
  const FrameRecord& rec = records_[i];
  if (base_ns_ < 0) base_ns_ = mono_now_ns() - (rec.t_ns - records_.front().t_ns);
  const std::int64_t exposure_start_ns = base_ns_ + (rec.t_ns - records_.front().t_ns);
  const auto exposure_ns = static_cast<std::int64_t>(rec.exposure.exposure_us * 1000.0);
  if (!sleep_until_or_stop(exposure_start_ns + exposure_ns, stop)) return SourceStatus::stopped;
  if (decoded_.load(std::memory_order_acquire) <= i) {
    waited_for_decoder_.store(waited_for_decoder_.load(std::memory_order_relaxed) + 1, std::memory_order_relaxed);
    while (decoded_.load(std::memory_order_acquire) <= i) {
      if (!sleep_until_or_stop(mono_now_ns() + kCapturePollNs, stop)) return SourceStatus::stopped;
    }
  }
  const Decoded& d = window_[i % window_.size()];
  slot.defect = d.defect;
  if (!slot.defect) d.gray.copyTo(slot.view.gray);  // same size and type: no allocation
  consumed_.store(i + 1, std::memory_order_release);
  slot.view.index = rec.index;
  slot.view.t_ns = exposure_start_ns;
  slot.view.exposure = rec.exposure;
  slot.truth = truth_[i];
  return SourceStatus::frame;
}

}  // namespace gvs::drivers
