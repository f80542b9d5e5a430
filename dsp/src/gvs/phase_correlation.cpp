// Phase correlation (see phase_correlation.hpp).
#include "gvs/dsp/phase_correlation.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include <opencv2/core.hpp>

#include "gvs/dsp/spectrum.hpp"
#include "peak_fit.hpp"
#include "search_spans.hpp"

namespace gvs::dsp {

namespace {

/// The lags (dr, dc) a search takes, exclude < |d| <= max, on a periodic
/// rows x cols surface (lag 0 at (0, 0); row r is lag r or r - rows).
struct SearchBand {
  int rows;
  int cols;
  double exclude_px;
  double max_px;

  [[nodiscard]] int lag_of_row(int r) const { return r < (rows + 1) / 2 ? r : r - rows; }
  [[nodiscard]] bool reaches(int dr) const { return static_cast<double>(dr * dr) <= max_px * max_px; }

  /// f(c, dc) for the columns of row lag `dr` inside the band, in column
  /// order (the order a full scan visits them, so ties resolve the same).
  template <class F>
  void for_each_column(int dr, F&& f) const {
    const detail::ColumnSpan a = detail::ring_span(dr, exclude_px, false, max_px, cols);
    if (a.empty()) return;
    const int last_positive = std::min(a.hi, (cols + 1) / 2 - 1);
    for (int dc = a.lo; dc <= last_positive; ++dc) f(dc, dc);
    for (int dc = std::max(-a.hi, (cols + 1) / 2 - cols); dc <= -std::max(a.lo, 1); ++dc) f(cols + dc, dc);
  }
};

}  // namespace

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
  row_max_.assign(static_cast<std::size_t>(size.height), 0.0f);
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

  // The surface RMS over every lag (four running sums: their adds do not
  // wait for each other).
  std::array<double, 4> lane_sq{};
  for (int r = 0; r < rows; ++r) {
    const float* s = surface_.ptr<float>(r);
    int c = 0;
    for (; c + 3 < cols; c += 4) {
      for (std::size_t l = 0; l < 4; ++l) {
        const auto v = static_cast<double>(s[c + static_cast<int>(l)]);
        lane_sq[l] += v * v;
      }
    }
    for (; c < cols; ++c) lane_sq[0] += static_cast<double>(s[c]) * static_cast<double>(s[c]);
  }
  const double sum_sq = (lane_sq[0] + lane_sq[1]) + (lane_sq[2] + lane_sq[3]);

  // Highest peak with exclude < |d| <= max, row by row over the rows the
  // search reaches; each row's highest value is kept for the second peak.
  const SearchBand band{rows, cols, exclude_radius_px, max_shift_px};
  float best = -std::numeric_limits<float>::infinity();
  int best_r = 0;
  int best_c = 0;
  for (int r = 0; r < rows; ++r) {
    row_max_[static_cast<std::size_t>(r)] = 0.0f;
    const int dr = band.lag_of_row(r);
    if (!band.reaches(dr)) continue;
    const float* s = surface_.ptr<float>(r);
    float row_best = 0.0f;
    band.for_each_column(dr, [&](int c, int dc) {
      const float v = s[c];
      row_best = std::max(row_best, v);
      if (v > best) {
        best = v;
        best_r = dr;
        best_c = dc;
      }
    });
    row_max_[static_cast<std::size_t>(r)] = row_best;
  }
  if (best == -std::numeric_limits<float>::infinity()) return out;
  // Second peak: highest value farther than 4 px from the first (and outside
  // the exclusion). Rows more than 4 px from it hold no lag near it: their
  // highest value stands; the nine rows near it are searched again.
  double second = 0.0;
  for (int r = 0; r < rows; ++r) {
    const int dr = band.lag_of_row(r);
    if (!band.reaches(dr)) continue;
    const int er = dr - best_r;
    if (er * er > 16) {
      second = std::max(second, static_cast<double>(row_max_[static_cast<std::size_t>(r)]));
      continue;
    }
    const float* s = surface_.ptr<float>(r);
    band.for_each_column(dr, [&](int c, int dc) {
      const int ec = dc - best_c;
      if (er * er + ec * ec > 16) second = std::max(second, static_cast<double>(s[c]));
    });
  }
  const detail::SubPixel p = detail::fit_extremum_3x3(surface_, best_r, best_c);
  const double rms = std::sqrt(sum_sq / static_cast<double>(rows * cols));
  out.found = true;
  out.d_row_px = p.d_row;
  out.d_col_px = p.d_col;
  out.peak = static_cast<double>(best);
  out.peak_to_rms = rms > 0.0 ? out.peak / rms : 0.0;
  out.second_ratio = out.peak > 0.0 ? second / out.peak : 1.0;
  return out;
}

}  // namespace gvs::dsp
