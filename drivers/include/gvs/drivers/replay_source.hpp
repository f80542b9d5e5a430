// `replay:DIR` frame source: a gvs-dataset played back at the pace of its
// timestamps. A decoder thread (normal scheduling: PNG decoding allocates)
// keeps a window of frames decoded ahead, so the capture thread only copies
// pixels and the memory held is the window's, whatever the dataset's length.
#pragma once

#include <atomic>
#include <cstdint>
#include <filesystem>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include <opencv2/core/mat.hpp>

#include "gvs/drivers/dataset.hpp"
#include "gvs/drivers/frame_source.hpp"

namespace gvs::drivers {

class ReplaySource final : public FrameSource {
 public:
  /// Reads the dataset's index and truth, decodes the first window of
  /// frames (`window_mb` of pixels, at least 4 frames) and starts the
  /// decoder thread. Throws std::runtime_error naming the folder when it
  /// cannot be read or no frame of the first window can be decoded.
  ReplaySource(const std::filesystem::path& folder, double window_mb);
  ~ReplaySource() override;
  ReplaySource(const ReplaySource&) = delete;
  ReplaySource& operator=(const ReplaySource&) = delete;

  /// The constructor's checks of the dataset's index, without decoding a
  /// frame (gvsd --check-config): the dataset's geometry and frame rate.
  struct Checked {
    core::CameraGeometry geometry;
    double fps = 0.0;
  };
  static Checked check(const std::filesystem::path& folder);

  [[nodiscard]] std::string describe() const override;
  [[nodiscard]] core::CameraGeometry geometry() const override { return geometry_; }
  [[nodiscard]] double nominal_fps() const override { return fps_; }
  void prepare(FrameSlot& slot) override;
  SourceStatus next(FrameSlot& slot, const std::atomic<bool>& stop) noexcept override;
  void set_exposure(const core::ExposurePlan&) noexcept override {}
  [[nodiscard]] bool controls_exposure() const override { return false; }
  [[nodiscard]] std::string health_text() const override;
  /// "replay: frame 12 gets no estimate: ..." for each frame that could not
  /// be decoded since the last call (the decoder finds them as it goes).
  std::vector<std::string> take_log_lines() override;

  /// Frames held decoded ahead.
  [[nodiscard]] std::size_t window_frames() const noexcept { return window_.size(); }

 private:
  struct Decoded {
    cv::Mat gray;                                ///< preallocated, the camera's size
    std::optional<core::RejectReason> defect;    ///< unreadable or wrong_size: delivered with no pixels
  };
  /// Decodes frame i into its window slot (i % window size); returns false
  /// if it is a defect (and queues its log line).
  bool decode_into_window(std::size_t i);
  void decoder_loop() noexcept;

  std::filesystem::path folder_;
  std::optional<DatasetReader> reader_;  ///< the decoder thread's, after the constructor
  core::CameraGeometry geometry_;
  std::vector<FrameRecord> records_;
  std::vector<FrameTruth> truth_;
  std::vector<Decoded> window_;
  double fps_ = 0.0;

  std::atomic<std::size_t> decoded_{0};   ///< frames [0, decoded_) have been decoded
  std::atomic<std::size_t> consumed_{0};  ///< frames the capture thread has copied out
  std::atomic<std::uint64_t> waited_for_decoder_{0};
  std::atomic<bool> quit_{false};
  mutable std::mutex log_mutex_;
  std::vector<std::string> log_lines_;
  std::thread decoder_;

  std::size_t next_ = 0;       ///< capture thread: the next frame to deliver
  std::int64_t base_ns_ = -1;  ///< monotonic time of the dataset's first t_ns
};

}  // namespace gvs::drivers
