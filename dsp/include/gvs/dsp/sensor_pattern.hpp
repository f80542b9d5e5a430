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
  /// mean - offset). Holds the pixels' own offsets (DSNU) and the light's
  /// fall-off. Each frame is the pattern plus its own ground and noise, and
  /// its ground is noise to the pattern: the frames are weighted by the
  /// inverse of that noise's variance (inverse-variance weighting, e.g.
  /// Bevington & Robinson, Data Reduction and Error Analysis, ch. 4),
  /// measured as the frame's fine-texture energy E (fine_texture_energy),
  /// and older frames fade with a time constant of 100 frames:
  ///   w = 1 / (E + 1),  W <- 0.99 W + w,  a = w / W.
  /// A plain mean of n frames keeps 1/n of their ground; blurred and dark
  /// frames, whose ground is nearly flat, now teach the pattern and sharp
  /// ones hardly do (docs/estimator.md, "Dark frames").
  void learn_pixels(const cv::Mat& gray, double mean_grey);

  /// One offset per column (grey levels), or nullptr before kColumnMinFrames.
  [[nodiscard]] const float* columns() const;
  /// One offset per pixel (CV_32F, grey levels); zero before any frame.
  [[nodiscard]] const cv::Mat& pixels() const { return pixels_; }
  /// Frames the per-pixel pattern is learnt from (counts up to 100).
  [[nodiscard]] int pixel_frames() const { return pixel_frames_; }

  /// Mean square step over kTextureStepPx pixels along rows and columns
  /// (grey levels^2): the frame's texture and noise through the filter
  /// |2 sin(k d / 2)|^2, d = 4 px, which peaks at |k| = pi/4 rad/px (8 px
  /// wavelength), where the streak length is measured. The step between
  /// neighbours would weigh the highest |k|, where the sensor noise rules;
  /// the light's fall-off, smooth across the frame, hardly counts in either.
  [[nodiscard]] static double fine_texture_energy(const cv::Mat& gray);
  static constexpr int kTextureStepPx = 4;

  /// Forget everything learnt (another camera, or a restart).
  void forget();

 private:
  std::vector<float> columns_;
  std::vector<double> column_sum_;  ///< learn_columns()'s working buffer
  int column_frames_ = 0;
  cv::Mat pixels_;  ///< CV_32F
  int pixel_frames_ = 0;
  double pixel_weight_sum_ = 0.0;  ///< W: the faded sum of the frames' weights
};

}  // namespace gvs::dsp
