// Displacement between the two images of a double-pulse exposure (PIV-like).
//
// Two short light pulses dt apart expose the ground twice:
//   g(x) = a s(x) + b s(x - d),  d = v dt / s_px  (image motion between pulses).
// Its autocorrelation is
//   R_g(t) = (a^2 + b^2) R_s(t) + a b (R_s(t - d) + R_s(t + d)),
// so side peaks at t = +-d give the displacement (Adrian 1991, PIV by
// autocorrelation). Weighting P(k) by |k|^2 (the autocorrelation of the
// gradient) sharpens the peaks to the texture's grain size.
//
// On a dark frame the texture stands above the sensor noise only up to some
// |k|, and the bins beyond, weighted most by |k|^2, add nothing but the
// noise's scatter to the surface. There each bin is also weighted by the
// Wiener gain of its ring, G = ((P - N0) / P)^2 (ring_gain()): close to 1
// where the texture rules, close to 0 where the noise does, as the
// weighting for delay estimation wants (a bin counts with the square of its
// SNR while that is small; Knapp & Carter 1976).
#include <algorithm>
#include <cmath>
#include <cstdint>

#include <opencv2/core.hpp>

#include "gvs/dsp/blur_analysis.hpp"
#include "peak_fit.hpp"
#include "search_spans.hpp"

namespace gvs::dsp {

DoubleImage BlurAnalyzer::double_image(const cv::Mat& spectrum, double min_px, double max_px, const RingGain* gain) {
  DoubleImage out;
  const double n0 = noise_floor(spectrum);
  // Only the columns the inverse DFT reads (DftPlan: 0 .. cols/2).
  const int half_cols = spectrum.cols / 2 + 1;
  for (int r = 0; r < spectrum.rows; ++r) {
    const double kr = k_row_[static_cast<std::size_t>(r)];
    const auto* f = spectrum.ptr<cv::Vec2f>(r);
    const float* w = double_band_.ptr<float>(r);
    auto* p = power_.ptr<cv::Vec2f>(r);
    const auto* rings = ring_.ptr<std::uint8_t>(r);
    for (int c = 0; c < half_cols; ++c) {
      const double kc = k_col_[static_cast<std::size_t>(c)];
      const double pw = static_cast<double>(w[c]) * gain_at(gain, rings, c) *
          (static_cast<double>(f[c][0] * f[c][0] + f[c][1] * f[c][1]) - n0);
      p[c] = cv::Vec2f(static_cast<float>(pw * (kr * kr + kc * kc)), 0.0f);
    }
  }
  inverse_dft_.run(power_, surface_);
  const double a0 = static_cast<double>(surface_.at<float>(0, 0));
  if (a0 <= 0.0) return out;
  // The side peak is looked for beyond the central peak, which is as wide
  // as the texture's grain in the band weighted (a dark frame's gain keeps
  // its lower |k|: 8-10 px): from the first minimum of the surface going
  // out along the rows, the columns and both diagonals. Inside, its flank
  // is higher than a side peak and would be taken for one (at the search's
  // inner edge), or make the side peak look not unique.
  const double inner_px = std::max(min_px, central_peak_radius_px(max_px));
  // Highest side peak in the half plane (the surface is even: A(-t) = A(t)):
  // row lags 0 .. rmax, on each the columns min <= |d| <= max, in the order
  // dc = -cmax .. cmax (ties resolve to the first). Each row's highest value
  // is kept for the second peak.
  const int rows = surface_.rows;
  const int cols = surface_.cols;
  const int rmax = std::min(rows / 2 - 2, static_cast<int>(max_px));
  const int cmax = std::min(cols / 2 - 2, static_cast<int>(max_px));
  // f(dc, value) over row lag dr's columns in the search, dc ascending.
  const auto for_each_lag = [&](int dr, auto&& f) {
    const detail::ColumnSpan a = detail::ring_span(dr, inner_px, true, max_px, cmax);
    if (a.empty()) return;
    const float* s = surface_.ptr<float>(dr);
    if (dr > 0) {
      for (int dc = -a.hi; dc <= -std::max(a.lo, 1); ++dc) f(dc, static_cast<double>(s[cols + dc]));
    }
    for (int dc = std::max(a.lo, dr > 0 ? 0 : 1); dc <= a.hi; ++dc) f(dc, static_cast<double>(s[dc]));
  };
  double best = -1e30;
  int best_r = 0;
  int best_c = 0;
  for (int dr = 0; dr <= rmax; ++dr) {
    double row_best = 0.0;
    for_each_lag(dr, [&](int dc, double v) {
      row_best = std::max(row_best, v);
      if (v > best) {
        best = v;
        best_r = dr;
        best_c = dc;
      }
    });
    row_max_[static_cast<std::size_t>(dr)] = row_best;
  }
  if (best <= 0.0) return out;
  // Second peak: away from the first by more than 5 px, and from its mirror
  // (it can reappear near dr = 0). Rows that hold no lag that near keep
  // their highest value; the others are searched again.
  double second = 0.0;
  for (int dr = 0; dr <= rmax; ++dr) {
    const int er = dr - best_r;
    const int mr = dr + best_r;
    if (er * er > 25 && mr * mr > 25) {
      second = std::max(second, row_max_[static_cast<std::size_t>(dr)]);
      continue;
    }
    for_each_lag(dr, [&](int dc, double v) {
      const int ec = dc - best_c;
      const int mc = dc + best_c;
      if (er * er + ec * ec <= 25 || mr * mr + mc * mc <= 25) return;
      second = std::max(second, v);
    });
  }
  // Sub-pixel fit on A divided by the window overlap, which would pull the
  // peak towards lag 0 (spectrum.hpp, WindowOverlap).
  const detail::SubPixel p = detail::fit_extremum_3x3_of(
      [this](int dr, int dc) { return detail::at_lag(surface_, dr, dc) / overlap_.at(dr, dc); }, best_r,
      best_c);
  out.found = true;
  out.d_row_px = p.d_row;
  out.d_col_px = p.d_col;
  out.height = best / a0;
  out.second_ratio = second / best;
  return out;
}

double BlurAnalyzer::central_peak_radius_px(double max_px) const {
  constexpr int kSteps[4][2] = {{0, 1}, {1, 0}, {1, 1}, {1, -1}};
  double radius = 0.0;
  for (const auto& step : kSteps) {
    const double step_px = std::hypot(step[0], step[1]);
    int n = 1;
    while ((n + 1) * step_px <= max_px && detail::at_lag(surface_, (n + 1) * step[0], (n + 1) * step[1]) <
                                             detail::at_lag(surface_, n * step[0], n * step[1])) {
      ++n;
    }
    radius = std::max(radius, n * step_px);
  }
  return radius;
}

void double_image_asymmetry(const cv::Mat& gray, DoubleImage& pair) {
  pair.asymmetry = 0.0;
  pair.skewness = 0.0;
  if (!pair.found || gray.empty()) return;
  const int dr = static_cast<int>(std::lround(pair.d_row_px));
  const int dc = static_cast<int>(std::lround(pair.d_col_px));
  const int r_lo = std::abs(dr);
  const int r_hi = gray.rows - std::abs(dr);
  const int c_lo = std::abs(dc);
  const int c_hi = gray.cols - std::abs(dc);
  if (r_hi - r_lo < 16 || c_hi - c_lo < 16) return;
  double sum = 0.0;
  std::int64_t n = 0;
  for (int r = r_lo; r < r_hi; r += 2) {
    const auto* g = gray.ptr<std::uint8_t>(r);
    for (int c = c_lo; c < c_hi; c += 2) {
      sum += g[c];
      ++n;
    }
  }
  const double m = sum / static_cast<double>(n);
  double c3_plus = 0.0;
  double c3_minus = 0.0;
  double m2 = 0.0;
  double m3 = 0.0;
  for (int r = r_lo; r < r_hi; r += 2) {
    const auto* g = gray.ptr<std::uint8_t>(r);
    const auto* gp = gray.ptr<std::uint8_t>(r + dr);
    const auto* gm = gray.ptr<std::uint8_t>(r - dr);
    for (int c = c_lo; c < c_hi; c += 2) {
      const double f = g[c] - m;
      const double f2 = f * f;
      c3_plus += f2 * (gp[c + dc] - m);
      c3_minus += f2 * (gm[c - dc] - m);
      m2 += f2;
      m3 += f2 * f;
    }
  }
  const double denom = std::abs(c3_plus) + std::abs(c3_minus);
  const double nn = static_cast<double>(n);
  if (denom <= 0.0 || m2 <= 0.0) return;
  pair.skewness = (m3 / nn) / std::pow(m2 / nn, 1.5);
  pair.asymmetry = (m3 >= 0.0 ? 1.0 : -1.0) * (c3_plus - c3_minus) / denom;
}

}  // namespace gvs::dsp
