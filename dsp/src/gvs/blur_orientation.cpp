// Axis of the motion blur from the orientation of the power spectrum.
//
// A streak of length L along the unit vector u multiplies the spectrum by
// sinc^2(L k.u / 2): for long streaks the energy lies along the line k.u = 0,
// perpendicular to the motion. The second moments
//   M = sum_k w(k) P(k) k k^T
// (by Parseval the image structure tensor sum grad(f) grad(f)^T) have their
// largest eigenvector along that line, so the motion axis u is the eigenvector
// of the smallest eigenvalue (Bigun & Granlund 1987, structure tensor).
// Working in the frequency domain with the exact k, inside a circular band,
// avoids the angle bias of finite-difference gradients on a square grid.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>

#include "gvs/dsp/blur_analysis.hpp"
#include "search_spans.hpp"

namespace gvs::dsp {

double BlurAnalyzer::gain_at(const RingGain* gain, const std::uint8_t* ring_row, int c) {
  if (gain == nullptr) return 1.0;
  const auto ring = static_cast<std::size_t>(ring_row[c]);
  return ring < gain->size() ? (*gain)[ring] : 0.0;
}

void BlurAnalyzer::ring_gain(const cv::Mat& spectrum, const StreakAxis* line, double half_width,
                             RingGain& gain) const {
  RingGain sum{};
  RingGain count{};
  for (int r = 0; r < spectrum.rows; ++r) {
    const double kr = k_row_[static_cast<std::size_t>(r)];
    const float* w = band_.ptr<float>(r);
    const auto* rings = ring_.ptr<std::uint8_t>(r);
    detail::StripColumns columns;
    if (line != nullptr) {
      columns = detail::strip_columns(spectrum.cols, kr * line->u_row, line->u_col, half_width);
    } else {
      columns.end[0] = spectrum.cols;
    }
    detail::for_each_half_power(spectrum, r, columns, [&](int c, float power, double m) {
      const double kc = k_col_[static_cast<std::size_t>(c)];
      if (w[c] == 0.0f) return;
      if (line != nullptr && std::abs(kr * line->u_row + kc * line->u_col) > half_width) return;
      const auto ring = static_cast<std::size_t>(rings[c]);
      if (ring >= sum.size()) return;
      sum[ring] += m * static_cast<double>(power);
      count[ring] += m;
    });
  }
  const double n0 = noise_floor(spectrum);
  for (std::size_t i = 0; i < gain.size(); ++i) {
    const double p = count[i] > 0.0 ? sum[i] / count[i] : 0.0;
    const double wiener = p > 0.0 ? std::max(0.0, p - n0) / p : 0.0;
    gain[i] = wiener * wiener;
  }
}

StreakAxis BlurAnalyzer::streak_axis(const cv::Mat& spectrum, const RingGain* gain) const {
  double m_rr = 0.0;
  double m_cc = 0.0;
  double m_rc = 0.0;
  const double n0 = noise_floor(spectrum);
  double signal = 0.0;
  double noise = 0.0;
  for (int r = 0; r < spectrum.rows; ++r) {
    const double kr = k_row_[static_cast<std::size_t>(r)];
    const float* w = band_.ptr<float>(r);
    const auto* rings = ring_.ptr<std::uint8_t>(r);
    // Two lanes of running sums (for_each_half_power_2lanes).
    std::array<double, 2> a_rr{}, a_cc{}, a_rc{}, row_signal{}, row_noise{};
    detail::for_each_half_power_2lanes(spectrum, r, 0, spectrum.cols, [&](int c, float power, double m, auto lane) {
      const double kc = k_col_[static_cast<std::size_t>(c)];
      const double band_power = m * static_cast<double>(w[c]) * (static_cast<double>(power) - n0);
      const double p = gain_at(gain, rings, c) * band_power;
      a_cc[lane] += p * kc * kc;
      a_rc[lane] += p * kc;
      a_rr[lane] += p;
      row_signal[lane] += band_power;  // the SNR without the gain
      row_noise[lane] += m * static_cast<double>(w[c]) * n0;
    });
    m_rr += (a_rr[0] + a_rr[1]) * kr * kr;
    m_rc += (a_rc[0] + a_rc[1]) * kr;
    m_cc += a_cc[0] + a_cc[1];
    signal += row_signal[0] + row_signal[1];
    noise += row_noise[0] + row_noise[1];
  }
  StreakAxis axis;
  axis.texture_snr = noise > 0.0 ? signal / noise : 1e9;
  const double half_diff = 0.5 * (m_rr - m_cc);
  const double root = std::sqrt(half_diff * half_diff + m_rc * m_rc);
  const double trace = m_rr + m_cc;
  if (trace <= 0.0) return axis;
  // Major eigenvector of M at angle theta from the row axis; motion is perpendicular.
  const double theta = 0.5 * std::atan2(2.0 * m_rc, m_rr - m_cc);
  axis.u_row = -std::sin(theta);
  axis.u_col = std::cos(theta);
  axis.anisotropy = 2.0 * root / trace;
  return axis;
}

double BlurAnalyzer::line_snr(const cv::Mat& spectrum, const StreakAxis& axis, double half_width) const {
  const double n0 = noise_floor(spectrum);
  double signal = 0.0;
  double noise = 0.0;
  for (int r = 0; r < spectrum.rows; ++r) {
    const double kr = k_row_[static_cast<std::size_t>(r)];
    const float* w = band_.ptr<float>(r);
    const detail::StripColumns columns = detail::strip_columns(spectrum.cols, kr * axis.u_row, axis.u_col, half_width);
    detail::for_each_half_power(spectrum, r, columns, [&](int c, float power, double m) {
      const double kc = k_col_[static_cast<std::size_t>(c)];
      if (std::abs(kr * axis.u_row + kc * axis.u_col) > half_width) return;
      signal += m * static_cast<double>(w[c]) * (static_cast<double>(power) - n0);
      noise += m * static_cast<double>(w[c]) * n0;
    });
  }
  return noise > 0.0 ? signal / noise : 0.0;
}

StreakAxis BlurAnalyzer::refine_axis(const cv::Mat& spectrum, const StreakAxis& start,
                                     double sigma, int iterations, bool high_k_weight,
                                     const RingGain* gain) const {
  // Iteratively reweighted moments: only energy within ~sigma of the line
  // k.u = 0 counts, weight exp(-(k.u)^2 / (2 sigma^2)). The off-line energy of
  // a finite streak (sinc^2 side lobes) carries the texture's own random
  // anisotropy; cutting it leaves the line, whose direction is exact.
  //
  // Along the line, the power P(k) of asphalt falls steeply with |k|: the
  // moments (weight P |k|^2) are ruled by the coarse stones near the
  // origin, where the line is short and its random wobble (each bin of a
  // random texture's periodogram scatters by 100 %) turns it most. With
  // high_k_weight each bin counts min(|k|, 1 rad/px)^2 more, i.e. the moments
  // of the second derivative's spectrum up to 1 rad/px: fixed 3 ms, 15-250
  // km/h on the simulator, 0.017-0.035 deg RMS (docs/estimator.md, "Streak
  // axis: weight of the line"; measurements: commit 0db0541). Above 1 rad/px
  // the sensor's noise and column pattern would gain too much; under-exposed
  // frames (texture SNR < 4) are left unweighted: weighted, their axis reads
  // 4.5 deg RMS at 5-15 km/h (same section).
  StreakAxis axis = start;
  const double cap2 = kLineWeightCap * kLineWeightCap;
  const double n0 = noise_floor(spectrum);
  const double inv2s2 = 1.0 / (2.0 * sigma * sigma);
  const double strip_half_width = std::sqrt(8.0 / inv2s2);
  for (int it = 0; it < iterations; ++it) {
    double m_rr = 0.0;
    double m_cc = 0.0;
    double m_rc = 0.0;
    for (int r = 0; r < spectrum.rows; ++r) {
      const double kr = k_row_[static_cast<std::size_t>(r)];
      const float* w = band_.ptr<float>(r);
      const auto* rings = ring_.ptr<std::uint8_t>(r);
      // Bins beyond g = 8 (|k.u| > 4 sigma) weigh less than exp(-8): skipped.
      const detail::StripColumns columns =
          detail::strip_columns(spectrum.cols, kr * axis.u_row, axis.u_col, strip_half_width);
      detail::for_each_half_power(spectrum, r, columns, [&](int c, float power, double m) {
        const double kc = k_col_[static_cast<std::size_t>(c)];
        const double ku = kr * axis.u_row + kc * axis.u_col;
        const double g = ku * ku * inv2s2;
        if (g > 8.0 || w[c] == 0.0f) return;
        const double k_weight =
            (high_k_weight ? std::min(kr * kr + kc * kc, cap2) : 1.0) * gain_at(gain, rings, c);
        const double p =
            m * static_cast<double>(w[c]) * std::exp(-g) * k_weight * (static_cast<double>(power) - n0);
        m_rr += p * kr * kr;
        m_cc += p * kc * kc;
        m_rc += p * kr * kc;
      });
    }
    if (m_rr + m_cc <= 0.0) break;
    const double theta = 0.5 * std::atan2(2.0 * m_rc, m_rr - m_cc);
    axis.u_row = -std::sin(theta);
    axis.u_col = std::cos(theta);
  }
  return axis;
}

}  // namespace gvs::dsp
