// The windowed Fourier spectrum every frequency-domain building block starts
// from, and the frequency grid that goes with it.
#pragma once

#include <vector>

#include <opencv2/core/mat.hpp>

#include "gvs/dsp/dft.hpp"

namespace gvs::dsp {

/// Fraction of each axis the spectrum window tapers (half at each border).
///
/// The window stops the frame borders from leaking a false "+" into the
/// spectrum (which would pull orientations towards 0/90 deg), but it also
/// throws texture away, and on asphalt the texture's own randomness is what
/// limits the streak axis: a Hann window (taper 1) keeps an effective 26 %
/// of the frame's area, this Tukey window (taper 0.25) 75 %, and the fixed
/// 3 ms direction at 60-140 km/h is sharper with it (docs/estimator.md,
/// "Building blocks"; measurements: commit fce183e).
inline constexpr double kWindowTaper = 0.25;

/// Tukey (tapered cosine) window of n samples: 1 in the middle, a raised
/// cosine over taper_fraction * n / 2 samples at each end (taper 1 = Hann).
std::vector<double> tukey_window(int n, double taper_fraction);

/// The 2-D spectrum window: tukey_window(rows) x tukey_window(cols).
cv::Mat spectrum_window(cv::Size size, int type, double taper_fraction = kWindowTaper);

/// Spectrum F(k) of a mean-removed, windowed image (spectrum_window):
///   f(x) = (g(x) - m) * w(x),  m = sum(g w) / sum(w),  F = DFT(f)
/// Buffers are made once; compute() does not allocate for images of the
/// configured size.
class WindowedSpectrum {
 public:
  /// `taper_fraction`: of the Tukey window (1: Hann). `transform`:
  /// forward_real_to_complex for the full spectrum, forward_real_to_half_complex
  /// when only the columns 0 .. cols/2 are read (the phase correlation).
  explicit WindowedSpectrum(cv::Size size, double taper_fraction = kWindowTaper,
                            DftPlan::Direction transform = DftPlan::Direction::forward_real_to_complex);

  /// `gray`: CV_8UC1 of the configured size (use a ROI for sub-windows).
  /// `spectrum`: complex spectrum, CV_32FC2, same size (the columns the
  /// transform writes: all, or 0 .. cols/2).
  /// `column_offsets` (optional, one per column, grey levels) are subtracted
  /// first: the sensor's column fixed-pattern noise, which otherwise looks
  /// exactly like an endless streak along the columns.
  void compute(const cv::Mat& gray, cv::Mat& spectrum, const float* column_offsets = nullptr);
  /// As above with one offset per pixel (`pixel_offsets`: CV_32F, same size
  /// as `gray`): the sensor's whole fixed pattern (GvsEstimator learns it).
  void compute(const cv::Mat& gray, cv::Mat& spectrum, const cv::Mat& pixel_offsets);

  [[nodiscard]] cv::Size size() const { return size_; }
  /// sum_x w(x)^2: white noise of variance sigma^2 per pixel has the mean
  /// power sigma^2 * window_energy() in every bin of the spectrum.
  [[nodiscard]] double window_energy() const { return window_energy_; }

 private:
  cv::Size size_;
  cv::Mat window_;  ///< CV_32F spectrum_window()
  double window_energy_ = 0.0;
  cv::Mat work_;    ///< CV_32F windowed image
  DftPlan dft_;  ///< forward, planned for size_ at construction
  double window_sum_ = 0.0;

  /// f = (g - offset - m) w with offset(r) a row of offsets (or nullptr).
  template <class RowOffsets>
  void compute_with(const cv::Mat& gray, cv::Mat& spectrum, RowOffsets row_offsets);
};

/// How much of the window WindowedSpectrum applies overlaps with itself
/// shifted by a lag (dr, dc), over the overlap at lag 0:
///   O(t) = sum_x w(x) w(x + t) / sum_x w(x)^2.
/// The autocorrelation of a windowed, statistically uniform image is the
/// image's own autocorrelation times O(t) (the expected autocovariance of a
/// tapered series; e.g. Percival & Walden 1993, Spectral Analysis for
/// Physical Applications). O falls off from 1 at lag 0, so it pulls
/// every side peak or trough towards lag 0 (about 0.1 px for a streak end at
/// 50 px with a Hann window; less with the flatter Tukey window). Dividing a
/// surface by O near a peak removes that pull. The window is separable, so
/// O(dr, dc) = O_rows(dr) O_cols(dc).
class WindowOverlap {
 public:
  explicit WindowOverlap(cv::Size size);
  /// O at integer lag (dr, dc); lags wrap like the DFT surface (-t == n - t).
  [[nodiscard]] double at(int dr, int dc) const;

 private:
  std::vector<double> rows_;  ///< O_rows(t), t = 0 .. height-1
  std::vector<double> cols_;
};

/// Angular frequency (rad/px) of DFT bin i of n: 2*pi*i/n, wrapped to [-pi, pi).
std::vector<double> angular_frequencies(int n);

}  // namespace gvs::dsp
