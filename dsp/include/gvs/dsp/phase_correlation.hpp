// Phase correlation: the shift between two frames of the ground texture.
//
//   R(k) = F_cur(k) F_prev*(k) / |F_cur(k) F_prev*(k)|,   r(x) = IDFT(R)
// If cur(x) = prev(x - d) then R(k) = exp(-i k.d) and r is a spike at x = d
// (Kuglin & Hines 1975). Fixed-pattern sensor noise does not move with the
// ground, so it adds a spike at d = 0: lags within `exclude_radius_px` of 0
// are never taken as the answer.
#pragma once

#include <vector>

#include <opencv2/core/mat.hpp>

#include "gvs/dsp/dft.hpp"

namespace gvs::dsp {

/// Shift of the texture in `current` relative to `previous`, in pixels.
struct ImageShift {
  bool found = false;
  double d_row_px = 0.0;
  double d_col_px = 0.0;
  double peak = 0.0;        ///< correlation peak height, ~ fraction of matching energy (0..1)
  double peak_to_rms = 0.0; ///< peak over the RMS of the surface: significance
  double second_ratio = 0.0;///< second-highest peak (away from the first) over the first
};

class PhaseCorrelator {
 public:
  /// `size`: spectra size; `max_frequency` (rad/px): frequencies above are
  /// dropped (they hold mostly noise once the frame is blurred).
  explicit PhaseCorrelator(cv::Size size, double max_frequency = 2.4);

  /// Spectra from WindowedSpectrum (CV_32FC2). Searches lags with
  /// exclude_radius_px < |d| <= max_shift_px.
  ImageShift correlate(const cv::Mat& spectrum_prev, const cv::Mat& spectrum_cur,
                       double exclude_radius_px, double max_shift_px);

  /// The last correlation surface r(x) (CV_32F, lag 0 at (0,0), periodic).
  [[nodiscard]] const cv::Mat& surface() const { return surface_; }

 private:
  cv::Mat weight_;  ///< CV_32F band limit per bin
  cv::Mat cross_;   ///< CV_32FC2 normalised cross-power spectrum; columns 0 .. cols/2 only
  cv::Mat surface_; ///< CV_32F
  std::vector<float> row_max_;  ///< per surface row, its highest value in the searched band
  DftPlan inverse_dft_;  ///< planned for `size` at construction
};

}  // namespace gvs::dsp
