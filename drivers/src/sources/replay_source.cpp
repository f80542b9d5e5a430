#include "gvs/drivers/replay_source.hpp"

#include <sstream>
#include <stdexcept>
#include <unordered_map>

#include "gvs/drivers/clock.hpp"

namespace gvs::drivers {

namespace {

/// What start-up checks of a dataset's index before it decodes a frame.
void check_index(const std::filesystem::path& folder, const std::vector<FrameRecord>& records,
                 const core::CameraGeometry& geometry, double preload_limit_mb) {
  if (records.empty()) throw std::runtime_error(folder.string() + ": the dataset has no frames");
  const double mb = static_cast<double>(records.size()) * geometry.width_px * geometry.height_px / 1048576.0;
  if (mb > preload_limit_mb) {
    std::ostringstream msg;
    msg << folder.string() << ": " << records.size() << " frames need " << mb
        << " MiB in memory, more than [source] replay_preload_limit_mb = " << preload_limit_mb
        << "; raise the limit or replay a shorter dataset";
    throw std::runtime_error(msg.str());
  }
}

}  // namespace

core::CameraGeometry ReplaySource::check(const std::filesystem::path& folder, double preload_limit_mb) {
  try {
    const DatasetReader reader(folder);
    check_index(folder, reader.frames(), reader.camera().geometry, preload_limit_mb);
    return reader.camera().geometry;
  } catch (const DatasetError& e) {
    throw std::runtime_error(std::string("replay: ") + e.what());
  }
}

ReplaySource::ReplaySource(const std::filesystem::path& folder, double preload_limit_mb) : folder_(folder) {
  try {
    const DatasetReader reader(folder);
    geometry_ = reader.camera().geometry;
    records_ = reader.frames();
    check_index(folder, records_, geometry_, preload_limit_mb);
    // A frame that cannot be decoded or has the wrong size is kept as a
    // defect: it is delivered in its turn with no pixels, gets no estimate
    // (named unreadable / wrong-size) and is counted, like a camera
    // frame that arrives broken; the frames around it play normally.
    frames_.reserve(records_.size());
    defects_.assign(records_.size(), std::nullopt);
    std::size_t good = 0;
    for (std::size_t i = 0; i < records_.size(); ++i) {
      cv::Mat gray;
      try {
        gray = reader.load_gray(i);
      } catch (const DatasetError& e) {
        load_warnings_.push_back("replay: frame " + std::to_string(records_[i].index) +
                                 " gets no estimate: " + e.what());
        defects_[i] = core::RejectReason::unreadable;
      }
      if (!defects_[i] && (gray.cols != geometry_.width_px || gray.rows != geometry_.height_px)) {
        std::ostringstream msg;
        msg << "replay: frame " << records_[i].index << " gets no estimate: " << records_[i].file << " is "
            << gray.cols << 'x' << gray.rows << " px but camera.json says " << geometry_.width_px << 'x'
            << geometry_.height_px;
        load_warnings_.push_back(msg.str());
        defects_[i] = core::RejectReason::wrong_size;
        gray.release();
      }
      if (!defects_[i]) ++good;
      frames_.push_back(std::move(gray));
    }
    if (good == 0) throw std::runtime_error(folder.string() + ": no frame of the dataset could be read");
    std::unordered_map<std::int64_t, const TruthRecord*> by_index;
    for (const auto& t : reader.truth()) by_index[t.index] = &t;
    truth_.resize(records_.size());
    for (std::size_t i = 0; i < records_.size(); ++i) {
      auto it = by_index.find(records_[i].index);
      if (it == by_index.end()) continue;
      const TruthRecord& t = *it->second;
      truth_[i] = FrameTruth{true, t.vx_mps, t.vy_mps, t.speed_mps, t.direction_deg.value_or(0.0), t.yaw_rate_dps};
    }
    if (records_.size() >= 2) {
      const double span_s = static_cast<double>(records_.back().t_ns - records_.front().t_ns) / 1e9;
      const auto steps = static_cast<double>(records_.back().index - records_.front().index);
      if (span_s > 0.0 && steps > 0.0) fps_ = steps / span_s;
    }
  } catch (const DatasetError& e) {
    throw std::runtime_error(std::string("replay: ") + e.what());
  }
}

std::string ReplaySource::describe() const {
  std::ostringstream s;
  s << "replay:" << folder_.string() << " (" << records_.size() << " frames, " << fps_ << " fps, "
    << geometry_.width_px << 'x' << geometry_.height_px << " px)";
  return s.str();
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
  slot.defect = defects_[i];
  if (!slot.defect) frames_[i].copyTo(slot.view.gray);  // same size and type: no allocation
  slot.view.index = rec.index;
  slot.view.t_ns = exposure_start_ns;
  slot.view.exposure = rec.exposure;
  slot.truth = truth_[i];
  return SourceStatus::frame;
}

}  // namespace gvs::drivers
