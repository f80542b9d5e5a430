// The camera sensor's fixed pattern: what every frame shows on top of the
// ground, learnt from frames of moving ground (where the texture averages
// out and only the sensor's offsets stay). Part of the estimator's
// TrackingState (gvs_tracking.hpp).
#pragma once

#include <vector>

#include <opencv2/core/mat.hpp>

namespace gvs::dsp {

class SensorPattern {
 public:
  /// Column offsets are used from this many frames learnt (columns()).
  static constexpr int kColumnMinFrames = 10;

  /// Buffers for frames of `size` are made here; learning does not allocate.
  explicit SensorPattern(cv::Size size);

  /// Column fixed-pattern noise: offset_c <- offset_c + a (mean of column c
  /// - frame mean - offset_c), a = 1/n for the first 50 frames (plain
  /// average), then 1/50 (slow EMA). Only from frames of fast motion, whose
  /// column means hold nothing else.
  void learn_columns(const cv::Mat& gray, double mean_grey);
  /// The whole pattern, per pixel: offset(r,c) <- offset + a (g(r,c) - frame
  /// mean - offset), a = 1/n for the first 100 frames, then 1/100. Holds the
  /// pixels' own offsets (DSNU) and the light's fall-off.
  void learn_pixels(const cv::Mat& gray, double mean_grey);

  /// One offset per column (grey levels), or nullptr before kColumnMinFrames.
  [[nodiscard]] const float* columns() const;
  /// One offset per pixel (CV_32F, grey levels); zero before any frame.
  [[nodiscard]] const cv::Mat& pixels() const { return pixels_; }
  /// Frames the per-pixel pattern is learnt from (counts up to 100).
  [[nodiscard]] int pixel_frames() const { return pixel_frames_; }

  /// Forget everything learnt (another camera, or a restart).
  void forget();

 private:
  std::vector<float> columns_;
  std::vector<double> column_sum_;  ///< learn_columns()'s working buffer
  int column_frames_ = 0;
  cv::Mat pixels_;  ///< CV_32F
  int pixel_frames_ = 0;
};

}  // namespace gvs::dsp
