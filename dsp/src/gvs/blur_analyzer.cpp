// BlurAnalyzer set-up: frequency grid and band-pass weight.
#include <algorithm>
#include <cmath>
#include <cstdint>

#include "gvs/dsp/blur_analysis.hpp"
#include "gvs/dsp/vocabulary.hpp"
#include "gvs/dsp/spectrum.hpp"
#include "search_spans.hpp"

namespace gvs::dsp {

BlurAnalyzer::BlurAnalyzer(cv::Size size)
    : k_row_(angular_frequencies(size.height)),
      k_col_(angular_frequencies(size.width)),
      overlap_(size),
      inverse_dft_(DftPlan::Direction::inverse_complex_to_real, size) {
  // Band [0.1, 2.2] rad/px with raised-cosine edges: drops the lighting
  // gradient and window leakage (low k) and pixel-level noise/aliasing (high k).
  band_.create(size, CV_32F);
  streak_band_.create(size, CV_32F);
  double_band_.create(size, CV_32F);
  ring_.create(size, CV_8U);
  for (int r = 0; r < size.height; ++r) {
    for (int c = 0; c < size.width; ++c) {
      const double k = std::hypot(k_row_[static_cast<std::size_t>(r)], k_col_[static_cast<std::size_t>(c)]);
      double w = 1.0;
      if (k < 0.05) {
        w = 0.0;
      } else if (k < 0.1) {
        w = 0.5 * (1.0 - std::cos((k - 0.05) / 0.05 * kPi));
      } else if (k > 2.6) {
        w = 0.0;
      } else if (k > 2.2) {
        w = 0.5 * (1.0 + std::cos((k - 2.2) / 0.4 * kPi));
      }
      band_.at<float>(r, c) = static_cast<float>(w);
      ring_.at<std::uint8_t>(r, c) = static_cast<std::uint8_t>(std::min(k / kRingWidth, 255.0));
      // Streak length only: also drop the coarse texture (stones of several
      // mm, wavelengths beyond ~30 px), whose few large features in a frame
      // tilt the autocorrelation around the streak end at random.
      const double coarse = 1.0 - std::exp(-k * k / (2.0 * kStreakHighPass * kStreakHighPass));
      streak_band_.at<float>(r, c) = static_cast<float>(w * coarse);
      // Double image only: the sensor's column fixed pattern is constant down
      // each column, so it lives in the rows k_row ~ 0 (+-2 bins of window
      // leakage) and makes a ridge of side peaks at every row lag (in dark
      // frames at high gain it won: speed 57 % RMS off, direction along the
      // columns). Drop those rows, as the phase correlation does.
      const int r_bin = r < (size.height + 1) / 2 ? r : size.height - r;
      double_band_.at<float>(r, c) = r_bin <= 2 ? 0.0f : static_cast<float>(w);
    }
  }
  // Columns past cols/2 are never read (DftPlan); the cepstrum writes its
  // surface over the whole buffer (streak_length_cepstral).
  power_ = cv::Mat::zeros(size, CV_32FC2);
  surface_.create(size, CV_32F);
  row_max_.assign(static_cast<std::size_t>(size.height), 0.0);
  // The noise floor's bins (noise_floor): in each row one run of columns
  // around k_col = +-pi (|k_col| rises to pi at the middle column).
  floor_cols_.assign(static_cast<std::size_t>(size.height), {0, 0});
  for (int r = 0; r < size.height; ++r) {
    const double kr = k_row_[static_cast<std::size_t>(r)];
    if (std::abs(kr) < kFloorMinKRow) continue;
    int first = -1;
    int last = -1;
    for (int c = 0; c < size.width; ++c) {
      const double kc = k_col_[static_cast<std::size_t>(c)];
      if (kr * kr + kc * kc < kFloorMinK * kFloorMinK) continue;
      if (first < 0) first = c;
      last = c;
    }
    if (first >= 0) floor_cols_[static_cast<std::size_t>(r)] = {first, last + 1};
  }
}

double BlurAnalyzer::noise_floor(const cv::Mat& spectrum) const {
  // Mean power over the bins with |k| >= 2.7 and |k_row| >= 1.9 (beyond the
  // texture's band, in the corners of the spectrum), where the bins are
  // listed per row at construction.
  double sum = 0.0;
  long n = 0;
  for (int r = 0; r < spectrum.rows; ++r) {
    const auto [first, end] = floor_cols_[static_cast<std::size_t>(r)];
    detail::for_each_half_power(spectrum, r, first, end,
                                [&sum](int, float power, double m) { sum += m * static_cast<double>(power); });
    n += end - first;
  }
  return n > 0 ? sum / static_cast<double>(n) : 0.0;
}

}  // namespace gvs::dsp
