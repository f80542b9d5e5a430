// Single-frame motion analysis from the power spectrum P(k) = |F(k)|^2 of a
// windowed frame (WindowedSpectrum):
//
//  - streak_axis():   the axis of the motion blur (orientation of P(k)).
//  - streak_length(): the length of the streak along that axis.
//  - double_image():  the displacement between the two images of a double pulse.
//
// All three see the motion only up to its sign: a streak or a pair of images
// looks the same whether the ground moved forwards or backwards.
//
// Every method reads only the spectrum's columns 0 .. cols/2 (DftPlan,
// forward_real_to_half_complex): the rest of a real image's spectrum is their
// conjugate mirror, of the same power.
#pragma once

#include <array>
#include <cstdint>
#include <utility>
#include <vector>

#include <opencv2/core/mat.hpp>

#include "gvs/dsp/dft.hpp"
#include "gvs/dsp/spectrum.hpp"

namespace gvs::dsp {

/// Axis of motion in image axes (unit vector (u_row, u_col), sign arbitrary).
struct StreakAxis {
  double u_row = 1.0;
  double u_col = 0.0;
  /// (l1 - l2)/(l1 + l2) of the spectral second moments: 0 = isotropic
  /// (no blur, or noise only), -> 1 = long streaks.
  double anisotropy = 0.0;
  /// sum (P - N0) / sum N0 over the band: texture power over sensor noise.
  double texture_snr = 0.0;
};

/// Streak (blur) length L, from the negative peak of the autocorrelation of
/// the derivative along the axis at lag +-L (see blur_length.cpp).
struct StreakLength {
  bool found = false;
  double length_px = 0.0;
  double d_row_px = 0.0;  ///< the lag of the peak: L times the (refined) axis
  double d_col_px = 0.0;
  /// -A(L)/A(0); ~0.5 for an ideal streak, ~0 when absent (streak_length()
  /// only: the cepstrum's c(0) is ~0 once each ring's mean is out, and its
  /// end is weighed by the significance alone).
  double depth = 0.0;
  /// -A(L) over the typical |A| along the rest of the axis: how far the
  /// streak end stands out of the texture and noise (a streak longer than the
  /// frame leaves only noise, with "peaks" as deep but not standing out).
  double significance = 0.0;
  double background = 0.0;  ///< that typical |A| over A(0): ~0.04 with a clean streak, >0.1 without (streak_length() only)
  /// Other ends along the ray at least 85 % as deep as the deepest and at
  /// least 4 px from this one: the surface alone cannot tell which is the
  /// streak's (streak_length() only; 0 from the cepstrum).
  int rivals = 0;
};

/// Displacement between the two images of a double exposure, from the side
/// peak of the image autocorrelation at lag +-d (see double_pulse.cpp).
struct DoubleImage {
  bool found = false;
  double d_row_px = 0.0;  ///< sign arbitrary (d or -d)
  double d_col_px = 0.0;
  double height = 0.0;    ///< side peak over the central peak: ab/(a^2+b^2) <= 0.5 ideally
  double second_ratio = 0.0; ///< next-highest side peak over the chosen one
  /// Third-order asymmetry, the sign test for unequal pulse energies:
  ///   C3(t) = mean(f(x)^2 f(x+t)),  f = grey - mean.
  /// For f = a s(x) + b s(x - d) (first image a, second b, texture s of
  /// skewness k3): C3(+d) - C3(-d) = a b (a - b) k3, and mean(f^3) has the
  /// sign of k3. So
  ///   asymmetry = sign(mean f^3) (C3(+d) - C3(-d)) / (|C3(+d)| + |C3(-d)|)
  /// is > 0 when d points from the stronger image to the weaker one.
  /// Filled by double_image_asymmetry().
  double asymmetry = 0.0;
  double skewness = 0.0;  ///< mean(f^3)/mean(f^2)^1.5 of the frame (how much to trust asymmetry)
};

class BlurAnalyzer {
 public:
  /// Gaussian high-pass (rad/px) of streak_length()'s weight: 1 - exp(-k^2 / (2 s^2)).
  static constexpr double kStreakHighPass = 0.2;

  explicit BlurAnalyzer(cv::Size size);

  /// White-noise power per bin (temporal and fixed-pattern noise), measured
  /// beyond the band (|k| > 2.7 rad/px) where the optics leave no texture.
  /// The building blocks below use P(k) - N0 (not clipped at 0: clipping
  /// would leave a third of the noise in).
  [[nodiscard]] double noise_floor(const cv::Mat& spectrum) const;
  static constexpr double kFloorMinK = 2.7;     ///< noise_floor(): |k| from here (rad/px)
  static constexpr double kFloorMinKRow = 1.9;  ///< ... and |k_row| from here

  /// Rings of |k| (width kRingWidth rad/px, from 0) for ring_gain().
  static constexpr int kRings = 64;
  static constexpr double kRingWidth = 0.05;
  using RingGain = std::array<double, kRings>;

  /// Weight per ring of |k| where the texture shows above the sensor noise:
  ///   G = (S / P)^2,  S = max(P - N0, 0),
  /// P the mean power on the ring: on the whole ring, or with `line` only
  /// within `half_width` (rad/px) of its line k.u = 0. For dark frames: the
  /// texture stands above the noise at low |k| only (asphalt's power falls
  /// steeply with |k|), and the bins beyond carry only the noise's random
  /// scatter, which the moments' |k|^2 would amplify. S/P is the Wiener
  /// filter's gain; its square was the best of the powers 1, 2 and 3 on
  /// the simulator's under-exposed runs (docs/estimator.md, "Dark frames").
  void ring_gain(const cv::Mat& spectrum, const StreakAxis* line, double half_width,
                 RingGain& gain) const;

  /// `gain` (optional): ring_gain() weights for each bin.
  [[nodiscard]] StreakAxis streak_axis(const cv::Mat& spectrum, const RingGain* gain = nullptr) const;

  /// Texture power over the noise on the line k.u = 0 of `axis` alone
  /// (within half_width rad/px of it):
  ///   SNR_line = sum w (P - N0) / sum w N0  over the strip.
  /// A streak of L px leaves about 1/L of the texture's power in the whole
  /// band but all of it on this line, so a long streak on fine ground is
  /// plain here while the band's SNR is small (docs/estimator.md, "Streaks
  /// longer than the frame").
  [[nodiscard]] double line_snr(const cv::Mat& spectrum, const StreakAxis& axis, double half_width) const;

  /// |k| (rad/px) up to which refine_axis() weights the line by |k|^2.
  static constexpr double kLineWeightCap = 1.0;

  /// Refines `start` by moments of the energy within ~sigma (rad/px) of the
  /// line k.u = 0 only (see blur_orientation.cpp). Keeps start's anisotropy.
  /// With `high_k_weight`, each bin also counts min(|k|, kLineWeightCap)^2
  /// times: the line's direction is sharpest far from the origin, where the
  /// coarse ground's own anisotropy is small (needs texture well above the
  /// sensor noise there). `gain` (optional): ring_gain() weights, as in
  /// streak_axis().
  [[nodiscard]] StreakAxis refine_axis(const cv::Mat& spectrum, const StreakAxis& start,
                                       double sigma, int iterations, bool high_k_weight = false,
                                       const RingGain* gain = nullptr) const;

  /// The anisotropy streak_axis() would measure on this ground for a streak
  /// of `length_px` along `axis`: the ground's power per ring of |k| read on
  /// the line k.u = 0, blurred by sinc^2(k.u L / 2) (blur_consistency.cpp).
  [[nodiscard]] double streak_anisotropy(const cv::Mat& spectrum, const StreakAxis& axis, double length_px) const;

  /// Searches min_px <= L <= max_px along `axis`. With expected_px > 0
  /// (a length predicted from a recent speed), of several streak ends at
  /// least 85 % as deep as the deepest, the one nearest to it (the others
  /// counted in `rivals`, with or without expected_px). With
  /// axis_tan > 0 (the tangent of how far the axis may be off), the end is
  /// looked for up to L * axis_tan px either side of the ray at each L.
  StreakLength streak_length(const cv::Mat& spectrum, const StreakAxis& axis, double min_px,
                             double max_px, double expected_px = 0.0, double axis_tan = 0.0);

  /// streak_length() again on the autocorrelation its last call made (same
  /// spectrum and axis), with another range or expected length: no power
  /// pass and no inverse DFT. streak_length_cepstral() leaves it as it is.
  StreakLength streak_length_again(double min_px, double max_px, double expected_px = 0.0,
                                   double axis_tan = 0.0);

  /// The same streak end read from the power cepstrum, IDFT(log P) less
  /// each ring's mean (see blur_cepstrum.cpp): the deepest negative point
  /// along `axis` in [min_px, max_px]. Fills found, length_px, d_row_px,
  /// d_col_px and significance (-C(L) over the typical |C| along the ray in
  /// that range); not depth, background or rivals.
  /// One more inverse DFT: for frames whose streak end needs vouching for.
  StreakLength streak_length_cepstral(const cv::Mat& spectrum, const StreakAxis& axis, double min_px,
                                      double max_px);

  /// Searches min_px <= |d| <= max_px in every direction. `gain`
  /// (optional): ring_gain() weights for each bin, for dark frames (see
  /// double_pulse.cpp).
  DoubleImage double_image(const cv::Mat& spectrum, double min_px, double max_px, const RingGain* gain = nullptr);

  /// The last autocorrelation surface (CV_32F, lag 0 at (0,0), periodic).
  [[nodiscard]] const cv::Mat& surface() const { return surface_; }

 private:
  /// double_image(): the lag (px) of the surface's first minimum going out
  /// from lag 0, the furthest along the rows, the columns and the diagonals.
  [[nodiscard]] double central_peak_radius_px(double max_px) const;

  std::vector<double> k_row_;
  std::vector<double> k_col_;
  cv::Mat band_;     ///< CV_32F band-pass weight per bin
  cv::Mat streak_band_;  ///< band_ times a high-pass (streak_length)
  cv::Mat double_band_;  ///< band_ without the column pattern's rows (double_image)
  /// CV_32FC2 weighted power spectrum (imaginary part 0), columns 0 .. cols/2
  /// only; streak_length_cepstral() writes its surface over it afterwards.
  cv::Mat power_;
  cv::Mat surface_;  ///< CV_32F autocorrelation
  StreakAxis surface_axis_;  ///< the axis streak_length() last weighted surface_ for
  std::vector<double> row_max_;  ///< double_image(): per row lag, its highest value in the search
  WindowOverlap overlap_;  ///< of the window the spectra were taken with (spectrum.hpp)
  DftPlan inverse_dft_;  ///< planned for `size` at construction
  std::array<double, 2048> ray_{};  ///< samples of A along the streak axis
  std::array<double, 2048> ray_across_{};  ///< ... and how far across it each was taken (px)

  cv::Mat ring_;     ///< CV_8U ring of |k| per bin (|k| / kRingWidth, at most 255)
  /// noise_floor()'s bins, per row: columns [first, second) (none: first == second).
  std::vector<std::pair<int, int>> floor_cols_;

  /// ring_gain()'s weight of bin c of a row of ring_; 1 without gains.
  static double gain_at(const RingGain* gain, const std::uint8_t* ring_row, int c);
};

/// Fills `pair.asymmetry` from the image itself (the sign test for unequal
/// pulse energies; see DoubleImage::asymmetry). `gray` is the frame.
void double_image_asymmetry(const cv::Mat& gray, DoubleImage& pair);

}  // namespace gvs::dsp
