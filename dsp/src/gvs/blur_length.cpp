// Streak length from the autocorrelation of the derivative along the streak.
//
// A streak of length L along u is the sharp texture s averaged over a segment:
//   b(x) = (1/L) integral_0^L s(x - t u) dt,
// so its derivative along u is a difference of two copies L apart:
//   d_u b(x) = (s(x) - s(x - L u)) / L.
// The autocorrelation of that derivative,
//   A(t) = (2 R_s(t) - R_s(t - L u) - R_s(t + L u)) / L^2,
// has negative peaks at t = +-L u (R_s: texture autocorrelation). In the
// frequency domain A = IDFT(P(k) (k.u)^2), one inverse DFT (P less the white
// noise floor, rolled off above |k.u| = 0.4 rad/px where noise dominates,
// and high-passed below |k| = 0.2 rad/px, see below). The peak's 2-D
// position also refines the axis. (Cf. Yitzhaky & Kopeika 1997, blur
// identification from the autocorrelation of the image derivative.)
//
// The term 2 R_s(t) does not vanish at t = L on asphalt: its stones (several
// mm, tens of pixels) leave a broad, uneven pedestal under the trough whose
// slope moves the trough by tenths of a pixel, differently on each patch of
// ground. Dropping |k| < 0.2 rad/px (wavelengths over ~30 px) takes that
// pedestal out, and rolling off at 0.4 rad/px keeps the noise that rules
// above it out of the trough; both were chosen by the scatter of L on
// simulated strobe frames (docs/estimator.md, "Building blocks";
// measurements: commit a15b63f; `gvs_sim_eval const adaptive normal`,
// 60-140 km/h: speed 0.62 % RMS). The sub-pixel fit divides out the
// window's overlap (spectrum.hpp).
#include <algorithm>
#include <cmath>

#include <opencv2/core.hpp>

#include "gvs/dsp/blur_analysis.hpp"
#include "peak_fit.hpp"

namespace gvs::dsp {

namespace {
constexpr double kAxialRollOff = 1.0 / (2.0 * 0.4 * 0.4);  // exp(-(k.u)^2 / (2 * 0.4^2))
}  // namespace

StreakLength BlurAnalyzer::streak_length(const cv::Mat& spectrum, const StreakAxis& axis,
                                         double min_px, double max_px, double expected_px,
                                         double axis_tan) {
  const double n0 = noise_floor(spectrum);
  // Only the columns the inverse DFT reads (DftPlan: 0 .. cols/2; the rest
  // is their mirror image).
  const int half_cols = spectrum.cols / 2 + 1;
  for (int r = 0; r < spectrum.rows; ++r) {
    const double kr = k_row_[static_cast<std::size_t>(r)];
    const auto* f = spectrum.ptr<cv::Vec2f>(r);
    const float* w = streak_band_.ptr<float>(r);
    auto* p = power_.ptr<cv::Vec2f>(r);
    for (int c = 0; c < half_cols; ++c) {
      const double ku = kr * axis.u_row + k_col_[static_cast<std::size_t>(c)] * axis.u_col;
      const double pw = static_cast<double>(w[c]) *
          (static_cast<double>(f[c][0] * f[c][0] + f[c][1] * f[c][1]) - n0);
      // (k.u)^2: the derivative along u. The Gaussian roll-off above 0.4 rad/px
      // keeps the sensor noise (white, unblurred) from swamping long streaks.
      const double ku2 = ku * ku;
      // exp(-x) ~ 1 / (1 + x + x^2/2 + x^3/6): same roll-off, no exp() per bin.
      const double x = ku2 * kAxialRollOff;
      const double roll_off = 1.0 / (1.0 + x * (1.0 + x * (0.5 + x / 6.0)));
      p[c] = cv::Vec2f(static_cast<float>(pw * ku2 * roll_off), 0.0f);
    }
  }
  inverse_dft_.run(power_, surface_);
  surface_axis_ = axis;
  return streak_length_again(min_px, max_px, expected_px, axis_tan);
}

StreakLength BlurAnalyzer::streak_length_again(double min_px, double max_px, double expected_px,
                                               double axis_tan) {
  StreakLength out;
  const StreakAxis& axis = surface_axis_;
  const double a0 = static_cast<double>(surface_.at<float>(0, 0));
  if (a0 <= 0.0) return out;

  // Deepest point of A along the ray t*u, t in [min, max] (half a pixel
  // steps). An axis off by an angle a puts the end t*tan(a) px beside the
  // ray, where a narrow trough is missed: then also across, n = u rotated by
  // 90 deg, up to t * axis_tan either side.
  double best = 1e30;
  double best_t = 0.0;
  double best_across = 0.0;
  std::size_t n_ray = 0;  // samples kept in ray_ for the choice below
  for (double t = min_px; t <= max_px; t += 0.5) {
    double v = detail::sample_lag(surface_, t * axis.u_row, t * axis.u_col);
    double across = 0.0;
    for (double a = 0.5; a <= t * axis_tan; a += 0.5) {
      for (const double s : {-a, a}) {
        const double va = detail::sample_lag(surface_, t * axis.u_row - s * axis.u_col, t * axis.u_col + s * axis.u_row);
        if (va < v) {
          v = va;
          across = s;
        }
      }
    }
    if (n_ray < ray_.size()) {
      ray_[n_ray] = v;
      ray_across_[n_ray++] = across;
    }
    if (v < best) {
      best = v;
      best_t = t;
      best_across = across;
    }
  }
  if (best >= 0.0) return out;
  const double deepest = best;
  // Two streak ends nearly as deep (texture grain can make a second one):
  // with an expected length, take the local minimum nearest to it among
  // those at least 85 % as deep as the deepest and at least 4 px from it
  // (a distinct end, not a ripple of the same one).
  if (expected_px > 0.0) {
    const double deepest_t = best_t;
    for (std::size_t i = 1; i + 1 < n_ray; ++i) {
      const double v = ray_[i];
      const double t = min_px + 0.5 * static_cast<double>(i);
      const bool local_min = v <= ray_[i - 1] && v <= ray_[i + 1];
      if (local_min && v <= 0.85 * deepest && std::abs(t - deepest_t) >= 4.0 &&
          std::abs(t - expected_px) < std::abs(best_t - expected_px)) {
        best = v;  // (the 2-D refinement below starts here)
        best_t = t;
        best_across = ray_across_[i];
      }
    }
  }
  // Rivals: the other ends as deep (the deepest among them, when the
  // expected length chose another), whichever end was chosen.
  for (std::size_t i = 1; i + 1 < n_ray; ++i) {
    const double v = ray_[i];
    const double t = min_px + 0.5 * static_cast<double>(i);
    if (v <= ray_[i - 1] && v <= ray_[i + 1] && v <= 0.85 * deepest && std::abs(t - best_t) >= 4.0) {
      ++out.rivals;
    }
  }
  // Background level: median |A| along the whole ray beyond the central lobe
  // (12 px .. 45 % of the frame extent), away from the candidate (robust to
  // the central lobe and to the peak itself).
  const double extent = std::abs(axis.u_row) * surface_.rows + std::abs(axis.u_col) * surface_.cols;
  std::size_t n = 0;
  for (double t = 12.0; t <= 0.45 * extent && n < ray_.size(); t += 0.5) {
    if (std::abs(t - best_t) < 6.0) continue;
    ray_[n++] = std::abs(detail::sample_lag(surface_, t * axis.u_row, t * axis.u_col));
  }
  const double rms = detail::median_spread(ray_, n);
  // Refine in 2-D: integer minimum in the 5x5 around the ray point, then a
  // quadratic fit, both on A divided by the window overlap (which would pull
  // the end towards lag 0: spectrum.hpp, WindowOverlap).
  const auto unwindowed = [this](int dr, int dc) {
    return detail::at_lag(surface_, dr, dc) / overlap_.at(dr, dc);
  };
  const int r0 = static_cast<int>(std::lround(best_t * axis.u_row - best_across * axis.u_col));
  const int c0 = static_cast<int>(std::lround(best_t * axis.u_col + best_across * axis.u_row));
  int br = r0;
  int bc = c0;
  double bv_unwindowed = unwindowed(r0, c0);
  for (int i = -2; i <= 2; ++i) {
    for (int j = -2; j <= 2; ++j) {
      const double v = unwindowed(r0 + i, c0 + j);
      if (v < bv_unwindowed) {
        bv_unwindowed = v;
        br = r0 + i;
        bc = c0 + j;
      }
    }
  }
  const detail::SubPixel p = detail::fit_extremum_3x3_of(unwindowed, br, bc);
  // Depth and significance stay on the windowed surface, like the background.
  const double bv = detail::at_lag(surface_, br, bc);
  out.found = true;
  out.d_row_px = p.d_row;
  out.d_col_px = p.d_col;
  out.length_px = std::hypot(p.d_row, p.d_col);
  out.depth = -bv / a0;
  out.significance = rms > 0.0 ? -bv / rms : 0.0;
  out.background = rms / a0;
  return out;
}

}  // namespace gvs::dsp
