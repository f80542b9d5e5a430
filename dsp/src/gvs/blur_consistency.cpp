// The elongation a streak of a given length would give this ground's
// spectrum: to tell a streak end from a trough of the texture's own grain
// in a spectrum of longer streaks.
//
// A streak of length L along u multiplies the ground's power S(k) by
// sinc^2(k.u L / 2) (blur_cepstrum.cpp). On the line k.u = 0 the factor is
// 1: there the frame shows the ground's own power, per ring of |k|. Asphalt
// is isotropic (no direction of its own), so S(k) = S(|k|) everywhere, and
// the second moments of S(|k|) sinc^2(k.u L / 2) over the band give the
// anisotropy that streak_axis() would measure for that L on this ground,
// whatever its grain: a fine grain keeps its power at high |k|, where even a
// short streak cuts deep, and is elongated by shorter streaks than a coarse one.
#include <algorithm>
#include <cmath>

#include "gvs/dsp/blur_analysis.hpp"
#include "gvs/dsp/vocabulary.hpp"

namespace gvs::dsp {

double BlurAnalyzer::streak_anisotropy(const cv::Mat& spectrum, const StreakAxis& axis, double length_px) const {
  const double n0 = noise_floor(spectrum);
  const int half_cols = spectrum.cols / 2 + 1;
  // The ground's power per ring, from the bins within 0.6 bin of the line.
  const double half_width = 0.6 * 2.0 * kPi / std::min(spectrum.rows, spectrum.cols);
  RingGain sum{};
  RingGain count{};
  for (int r = 0; r < spectrum.rows; ++r) {
    const double kr = k_row_[static_cast<std::size_t>(r)];
    const auto* f = spectrum.ptr<cv::Vec2f>(r);
    const auto* rings = ring_.ptr<std::uint8_t>(r);
    for (int c = 0; c < half_cols; ++c) {
      const double ku = kr * axis.u_row + k_col_[static_cast<std::size_t>(c)] * axis.u_col;
      const auto ring = static_cast<std::size_t>(rings[c]);
      if (std::abs(ku) > half_width || ring >= sum.size()) continue;
      sum[ring] += static_cast<double>(f[c][0] * f[c][0] + f[c][1] * f[c][1]) - n0;
      count[ring] += 1.0;
    }
  }
  RingGain ground{};
  for (std::size_t i = 0; i < ground.size(); ++i) {
    ground[i] = count[i] > 0.0 ? std::max(0.0, sum[i] / count[i]) : 0.0;
  }
  // The moments streak_axis() takes, of S(|k|) sinc^2(k.u L / 2).
  // Along a row x = k.u L / 2 grows by the same step from column to column
  // (k_col = 2 pi c / cols up to the Nyquist column, which is -pi), so
  // sin x follows by the angle-addition rule,
  //   sin(x + d) = sin x cos d + cos x sin d,  cos(x + d) = cos x cos d - sin x sin d,
  // a few multiplications per bin in place of a sine (rounding grows by
  // about 1e-16 a step).
  const int rising_cols = std::min(half_cols, (spectrum.cols + 1) / 2);
  const double step = 0.5 * length_px * axis.u_col * 2.0 * kPi / spectrum.cols;
  const double cos_step = std::cos(step);
  const double sin_step = std::sin(step);
  double m_rr = 0.0;
  double m_cc = 0.0;
  double m_rc = 0.0;
  for (int r = 0; r < spectrum.rows; ++r) {
    const double kr = k_row_[static_cast<std::size_t>(r)];
    const float* w = band_.ptr<float>(r);
    const auto* rings = ring_.ptr<std::uint8_t>(r);
    const double x0 = 0.5 * length_px * kr * axis.u_row;
    double sin_x = std::sin(x0);
    double cos_x = std::cos(x0);
    for (int c = 0; c < half_cols; ++c) {
      const double kc = k_col_[static_cast<std::size_t>(c)];
      const double x = 0.5 * length_px * (kr * axis.u_row + kc * axis.u_col);
      const double sin_now = c < rising_cols ? sin_x : std::sin(x);
      const double next_sin = sin_x * cos_step + cos_x * sin_step;
      cos_x = cos_x * cos_step - sin_x * sin_step;
      sin_x = next_sin;
      const auto ring = static_cast<std::size_t>(rings[c]);
      if (w[c] == 0.0f || ring >= ground.size()) continue;
      const double sinc = std::abs(x) < 1e-9 ? 1.0 : sin_now / x;
      const double p = static_cast<double>(w[c]) * ground[ring] * sinc * sinc;
      m_rr += p * kr * kr;
      m_cc += p * kc * kc;
      m_rc += p * kr * kc;
    }
  }
  const double trace = m_rr + m_cc;
  if (trace <= 0.0) return 0.0;
  const double half_diff = 0.5 * (m_rr - m_cc);
  return 2.0 * std::sqrt(half_diff * half_diff + m_rc * m_rc) / trace;
}

}  // namespace gvs::dsp
