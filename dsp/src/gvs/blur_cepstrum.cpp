// Streak length from the power cepstrum: a second reading of L, to vouch for
// a faint streak end that streak_length() found.
//
// A streak of length L along u multiplies the texture's power by
//   |H(k)|^2 = sinc^2(k.u L / 2),
// zero on the lines k.u = 2 pi n / L. In the logarithm the texture and the
// blur add, log P = log S + log |H|^2 (where S stands above the noise), and
// since log |sin x|^2 = -2 log 2 - 2 sum_n cos(2 n x) / n, the inverse DFT
// of log |H|^2 has negative peaks at the lags +-n L u, of weight 1/n
// (Cannon 1976, "Blind deconvolution of spatially invariant image blurs
// with phase", IEEE Trans. ASSP 24(1)). Each ring of |k|'s mean of log P,
// which holds the texture's own spectrum log S(|k|), is taken out first.
// Every zero then counts alike however little texture power lies there,
// where streak_length()'s (k.u)^2 P leans on the few |k| where a steep
// texture spectrum is strongest; the bins count by ring_gain() (only where
// the texture shows above the noise).
#include <algorithm>
#include <cmath>

#include <opencv2/core.hpp>

#include "gvs/dsp/blur_analysis.hpp"
#include "peak_fit.hpp"

namespace gvs::dsp {

StreakLength BlurAnalyzer::streak_length_cepstral(const cv::Mat& spectrum, const StreakAxis& axis,
                                                  double min_px, double max_px) {
  StreakLength out;
  const double n0 = noise_floor(spectrum);
  if (!(n0 > 0.0)) return out;
  RingGain gain{};
  ring_gain(spectrum, nullptr, 0.0, gain);
  // log P per bin (floored a thousandth of the noise below, where the
  // periodogram of noise alone rarely goes), and each ring's mean of it.
  RingGain log_sum{};
  RingGain count{};
  const int half_cols = spectrum.cols / 2 + 1;
  const auto floor_power = static_cast<float>(1e-3 * n0);
  for (int r = 0; r < spectrum.rows; ++r) {
    const auto* f = spectrum.ptr<cv::Vec2f>(r);
    const auto* rings = ring_.ptr<std::uint8_t>(r);
    auto* p = power_.ptr<cv::Vec2f>(r);
    for (int c = 0; c < half_cols; ++c) {
      const float log_p = std::log(std::max(f[c][0] * f[c][0] + f[c][1] * f[c][1], floor_power));
      p[c] = cv::Vec2f(log_p, 0.0f);
      const auto ring = static_cast<std::size_t>(rings[c]);
      if (ring >= log_sum.size()) continue;
      log_sum[ring] += static_cast<double>(log_p);
      count[ring] += 1.0;
    }
  }
  for (std::size_t i = 0; i < log_sum.size(); ++i) {
    if (count[i] > 0.0) log_sum[i] /= count[i];
  }
  for (int r = 0; r < spectrum.rows; ++r) {
    const float* w = band_.ptr<float>(r);
    const auto* rings = ring_.ptr<std::uint8_t>(r);
    auto* p = power_.ptr<cv::Vec2f>(r);
    for (int c = 0; c < half_cols; ++c) {
      const auto ring = static_cast<std::size_t>(rings[c]);
      const double weight = ring < gain.size() ? static_cast<double>(w[c]) * gain[ring] : 0.0;
      const double mean = ring < log_sum.size() ? log_sum[ring] : 0.0;
      p[c] = cv::Vec2f(static_cast<float>(weight * (static_cast<double>(p[c][0]) - mean)), 0.0f);
    }
  }
  // Into power_'s own memory (the inverse reads its input into FFTW's
  // buffer first), so the autocorrelation in surface_ stays for
  // streak_length_again().
  cv::Mat cepstrum(power_.size(), CV_32F, power_.data);
  inverse_dft_.run(power_, cepstrum);

  // The deepest point along the ray t u, t in [min, max], in half pixels.
  double best = 0.0;
  double best_t = 0.0;
  for (double t = min_px; t <= max_px; t += 0.5) {
    const double v = detail::sample_lag(cepstrum, t * axis.u_row, t * axis.u_col);
    if (v < best) {
      best = v;
      best_t = t;
    }
  }
  if (best >= 0.0) return out;
  // How far the end stands out of the ray (as in streak_length()): over the
  // typical |c| along it, away from the end. Under a streak longer than
  // the range the deepest point is only the least positive one, and
  // barely stands out.
  std::size_t n = 0;
  for (double t = std::max(12.0, min_px); t <= max_px && n < ray_.size(); t += 0.5) {
    if (std::abs(t - best_t) < 6.0) continue;
    ray_[n++] = std::abs(detail::sample_lag(cepstrum, t * axis.u_row, t * axis.u_col));
  }
  const double spread = detail::median_spread(ray_, n);
  // Integer minimum in the 5x5 around it, then a quadratic fit (as
  // streak_length(); no window overlap to divide out: the window fills the
  // zeros of |H|^2 alike at every lag).
  const int r0 = static_cast<int>(std::lround(best_t * axis.u_row));
  const int c0 = static_cast<int>(std::lround(best_t * axis.u_col));
  int br = r0;
  int bc = c0;
  for (int i = -2; i <= 2; ++i) {
    for (int j = -2; j <= 2; ++j) {
      if (detail::at_lag(cepstrum, r0 + i, c0 + j) < detail::at_lag(cepstrum, br, bc)) {
        br = r0 + i;
        bc = c0 + j;
      }
    }
  }
  const detail::SubPixel p = detail::fit_extremum_3x3(cepstrum, br, bc);
  out.found = true;
  out.d_row_px = p.d_row;
  out.d_col_px = p.d_col;
  out.length_px = std::hypot(p.d_row, p.d_col);
  out.significance = spread > 0.0 ? -detail::at_lag(cepstrum, br, bc) / spread : 0.0;
  return out;
}

}  // namespace gvs::dsp
