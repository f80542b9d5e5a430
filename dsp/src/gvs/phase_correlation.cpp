// Phase correlation (see phase_correlation.hpp).
#include "gvs/dsp/phase_correlation.hpp"

#include <cmath>

#include <opencv2/core.hpp>

#include "gvs/dsp/spectrum.hpp"
#include "peak_fit.hpp"

namespace gvs::dsp {

PhaseCorrelator::PhaseCorrelator(cv::Size size, double max_frequency)
    : inverse_dft_(DftPlan::Direction::inverse_complex_to_real, size) {
  const std::vector<double> kr = angular_frequencies(size.height);
  const std::vector<double> kc = angular_frequencies(size.width);
  weight_.create(size, CV_32F);
  for (int r = 0; r < size.height; ++r) {
    for (int c = 0; c < size.width; ++c) {
      const double k = std::hypot(kr[static_cast<std::size_t>(r)], kc[static_cast<std::size_t>(c)]);
      // Smooth roll-off (raised cosine) over the top 30 % of the band.
      const double x = (k - 0.7 * max_frequency) / (0.3 * max_frequency);
      double w = 1.0;
      if (x >= 1.0) {
        w = 0.0;
      } else if (x > 0.0) {
        w = 0.5 * (1.0 + std::cos(x * 3.141592653589793));
      }
      // The sensor's column fixed-pattern noise is constant down each
      // column: it lives in the spectrum rows k_row ~ 0 (+-2 bins of window
      // leakage) and would correlate at every row shift. Drop those rows.
      const int r_bin = r < (size.height + 1) / 2 ? r : size.height - r;
      if (r_bin <= 2) w = 0.0;
      // Below 0.1 rad/px (periods > 60 px) the fixed lighting pattern of the
      // LED ring dominates the phase and pulls the peak towards lag 0.
      if (k < 0.05) {
        w = 0.0;
      } else if (k < 0.1) {
        w *= 0.5 * (1.0 - std::cos((k - 0.05) / 0.05 * 3.141592653589793));
      }
      weight_.at<float>(r, c) = static_cast<float>(w);
    }
  }
  cross_ = cv::Mat::zeros(size, CV_32FC2);  // the columns past cols/2 stay 0, never read
  surface_.create(size, CV_32F);
}

ImageShift PhaseCorrelator::correlate(const cv::Mat& spectrum_prev, const cv::Mat& spectrum_cur,
                                      double exclude_radius_px, double max_shift_px) {
  ImageShift out;
  const int rows = cross_.rows;
  const int cols = cross_.cols;
  // R = F_cur F_prev* / |F_cur F_prev*|, band-limited; only the columns
  // the inverse DFT reads (DftPlan: 0 .. cols/2; R(-k) = R(k)* gives the rest).
  const int half_cols = cols / 2 + 1;
  for (int r = 0; r < rows; ++r) {
    const auto* a = spectrum_cur.ptr<cv::Vec2f>(r);
    const auto* b = spectrum_prev.ptr<cv::Vec2f>(r);
    const float* w = weight_.ptr<float>(r);
    auto* x = cross_.ptr<cv::Vec2f>(r);
    for (int c = 0; c < half_cols; ++c) {
      const float re = a[c][0] * b[c][0] + a[c][1] * b[c][1];
      const float im = a[c][1] * b[c][0] - a[c][0] * b[c][1];
      const float mag = std::sqrt(re * re + im * im) + 1e-20f;
      x[c] = cv::Vec2f(re / mag * w[c], im / mag * w[c]);
    }
  }
  inverse_dft_.run(cross_, surface_);

  // Highest peak with exclude < |d| <= max, and the surface RMS.
  const double ex2 = exclude_radius_px * exclude_radius_px;
  const double mx2 = max_shift_px * max_shift_px;
  double best = -1e30;
  int best_r = 0;
  int best_c = 0;
  double sum_sq = 0.0;
  for (int r = 0; r < rows; ++r) {
    const int dr = r < (rows + 1) / 2 ? r : r - rows;
    const float* s = surface_.ptr<float>(r);
    for (int c = 0; c < cols; ++c) {
      const double v = static_cast<double>(s[c]);
      sum_sq += v * v;
      const int dc = c < (cols + 1) / 2 ? c : c - cols;
      const double d2 = static_cast<double>(dr * dr + dc * dc);
      if (d2 <= ex2 || d2 > mx2) continue;
      if (v > best) {
        best = v;
        best_r = dr;
        best_c = dc;
      }
    }
  }
  if (best <= -1e29) return out;
  // Second peak: highest value farther than 4 px from the first (and outside the exclusion).
  double second = 0.0;
  for (int r = 0; r < rows; ++r) {
    const int dr = r < (rows + 1) / 2 ? r : r - rows;
    const float* s = surface_.ptr<float>(r);
    for (int c = 0; c < cols; ++c) {
      const int dc = c < (cols + 1) / 2 ? c : c - cols;
      const double d2 = static_cast<double>(dr * dr + dc * dc);
      if (d2 <= ex2 || d2 > mx2) continue;
      const int er = dr - best_r;
      const int ec = dc - best_c;
      if (er * er + ec * ec <= 16) continue;
      second = std::max(second, static_cast<double>(s[c]));
    }
  }
  const detail::SubPixel p = detail::fit_extremum_3x3(surface_, best_r, best_c);
  const double rms = std::sqrt(sum_sq / static_cast<double>(rows * cols));
  out.found = true;
  out.d_row_px = p.d_row;
  out.d_col_px = p.d_col;
  out.peak = best;
  out.peak_to_rms = rms > 0.0 ? best / rms : 0.0;
  out.second_ratio = best > 0.0 ? second / best : 1.0;
  return out;
}

}  // namespace gvs::dsp
