// Thesis baseline, part 3: speed from the Laplacian (gvs-thesis-2022 section
// 5.3). The more the texture is motion-blurred, the smaller the second
// derivative of the image, so the standard deviation of the Laplacian falls
// as speed rises. An inverse model made of exponential pieces turns that
// standard deviation into a speed.
#pragma once

#include <cstddef>
#include <span>

#include <opencv2/core/mat.hpp>

namespace gvs::dsp::thesis {

struct LaplacianConfig {
  /// Radius of the cross structuring element of the morphology step. The
  /// thesis used 5 px at about 0.046 mm/px (50 mm over 1080 px); this keeps
  /// the same size on the ground: round(0.23 mm / mm_per_px), at least 1.
  double morph_radius_mm = 0.23;
  int laplacian_ksize = 3;  ///< thesis Fig. A.6: Laplacian(frame, lap, CV_64F, 3)
};

/// One exponential sub-model of the direct model lap_std(v) = a * exp(b * v),
/// valid for speeds in [speed_lo_mps, speed_hi_mps] (thesis Fig. 5.7).
struct LaplacianSegment {
  double speed_lo_mps = 0.0;
  double speed_hi_mps = 0.0;
  double a = 0.0;  ///< lap_std at v = 0 of this piece (grey levels per px^2)
  double b = 0.0;  ///< 1/(m/s); negative: blur lowers lap_std
};

/// Inverse of a piecewise exponential model: v = ln(lap_std / a) / b on the
/// piece whose lap_std range contains the measurement (thesis 5.3: "the
/// switching points are the limits of the inverted functions").
struct LaplacianSpeed {
  bool ok = false;
  double speed_mps = 0.0;
  bool clamped = false;  ///< lap_std outside the model's range: speed clamped to its end
  double quality = 0.0;
};
LaplacianSpeed invert_laplacian_model(double lap_std, std::span<const LaplacianSegment> model);

/// The model fitted on gvs's simulator (see thesis_laplacian.cpp for the
/// command that produced it). Empty when not fitted yet.
std::span<const LaplacianSegment> fitted_laplacian_model();

/// Morphological closing (cross element), Laplacian, standard
/// deviation. Buffers are kept between calls.
class LaplacianBlur {
 public:
  LaplacianBlur(double mm_per_px, const LaplacianConfig& config = {});
  /// Standard deviation of the Laplacian of the frame (grey levels per px^2);
  /// negative when the frame is empty or not CV_8UC1.
  double lap_std(const cv::Mat& gray);

 private:
  cv::Mat element_;
  cv::Mat morph_;
  cv::Mat lap_;
  int ksize_ = 3;
};

}  // namespace gvs::dsp::thesis
