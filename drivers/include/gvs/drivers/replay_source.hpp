// `replay:DIR` frame source: a gvs-dataset played back at
// the pace of its timestamps. The frames are decoded into memory at start-up
// (PNG decoding allocates), so the capture thread only copies pixels.
#pragma once

#include <atomic>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <opencv2/core/mat.hpp>

#include "gvs/drivers/frame_source.hpp"
#include "gvs/drivers/dataset.hpp"

namespace gvs::drivers {

class ReplaySource final : public FrameSource {
 public:
  /// Throws std::runtime_error naming the folder when it cannot be read or
  /// is larger than `preload_limit_mb`.
  ReplaySource(const std::filesystem::path& folder, double preload_limit_mb);
  /// The constructor's checks of the dataset's index, without decoding a
  /// frame (gvsd --check-config). Returns the dataset's geometry.
  static core::CameraGeometry check(const std::filesystem::path& folder, double preload_limit_mb);

  [[nodiscard]] std::string describe() const override;
  [[nodiscard]] core::CameraGeometry geometry() const override { return geometry_; }
  [[nodiscard]] double nominal_fps() const override { return fps_; }
  void prepare(FrameSlot& slot) override;
  SourceStatus next(FrameSlot& slot, const std::atomic<bool>& stop) noexcept override;
  void set_exposure(const core::ExposurePlan&) noexcept override {}
  [[nodiscard]] bool controls_exposure() const override { return false; }

  /// One line per frame that could not be loaded and will get no estimate
  /// ("frame 12 gets no estimate: ..."), for the caller's log.
  [[nodiscard]] const std::vector<std::string>& load_warnings() const noexcept { return load_warnings_; }

 private:
  std::filesystem::path folder_;
  core::CameraGeometry geometry_;
  std::vector<FrameRecord> records_;
  std::vector<cv::Mat> frames_;
  std::vector<std::optional<core::RejectReason>> defects_;  ///< per frame: none, unreadable or wrong_size
  std::vector<FrameTruth> truth_;
  std::vector<std::string> load_warnings_;
  double fps_ = 0.0;
  std::size_t next_ = 0;
  std::int64_t base_ns_ = -1;  ///< monotonic time of the dataset's first t_ns
};

}  // namespace gvs::drivers
