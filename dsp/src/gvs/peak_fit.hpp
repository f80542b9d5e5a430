// Sub-pixel peak location on a periodic (DFT) correlation surface.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>

#include <opencv2/core/mat.hpp>

namespace gvs::dsp::detail {

/// Value of a CV_32F periodic surface at integer lag (dr, dc) (wraps around).
inline double at_lag(const cv::Mat& s, int dr, int dc) {
  const int r = ((dr % s.rows) + s.rows) % s.rows;
  const int c = ((dc % s.cols) + s.cols) % s.cols;
  return static_cast<double>(s.at<float>(r, c));
}

/// Bilinear sample of a periodic CV_32F surface at a fractional lag.
inline double sample_lag(const cv::Mat& s, double dr, double dc) {
  const double fr = std::floor(dr);
  const double fc = std::floor(dc);
  const double ar = dr - fr;
  const double ac = dc - fc;
  const int r0 = static_cast<int>(fr);
  const int c0 = static_cast<int>(fc);
  return (1 - ar) * ((1 - ac) * at_lag(s, r0, c0) + ac * at_lag(s, r0, c0 + 1)) +
         ar * ((1 - ac) * at_lag(s, r0 + 1, c0) + ac * at_lag(s, r0 + 1, c0 + 1));
}

struct SubPixel {
  double d_row = 0.0;
  double d_col = 0.0;
  double value = 0.0;
};

/// Extremum (peak or trough) of the quadratic f = a + b x + c y + d x^2 + e y^2 + g x y fitted
/// by least squares to the 3x3 neighbourhood of the integer extremum (r, c).
/// Unlike two separate 1-D parabolas this follows peaks tilted by an oblique
/// blur. Falls back to the integer position when the fit is degenerate or
/// lands more than a pixel away.
/// `value(dr, dc)` gives the surface at an integer lag (e.g. at_lag, or
/// at_lag divided by the window overlap).
template <class ValueAt>
SubPixel fit_extremum_3x3_of(ValueAt&& value, int r, int c) {
  double f[3][3];
  for (int i = -1; i <= 1; ++i)
    for (int j = -1; j <= 1; ++j) f[i + 1][j + 1] = value(r + i, c + j);
  // Least-squares coefficients on the 3x3 grid (x = row offset, y = col offset).
  double b = 0, cc = 0, d = 0, e = 0, g = 0, sum = 0;
  for (int i = -1; i <= 1; ++i) {
    for (int j = -1; j <= 1; ++j) {
      const double v = f[i + 1][j + 1];
      sum += v;
      b += i * v;
      cc += j * v;
      g += i * j * v;
    }
  }
  b /= 6.0;
  cc /= 6.0;
  g /= 4.0;
  double sxx = 0, syy = 0;
  for (int i = -1; i <= 1; ++i)
    for (int j = -1; j <= 1; ++j) {
      sxx += (i * i) * f[i + 1][j + 1];
      syy += (j * j) * f[i + 1][j + 1];
    }
  // d = (sum_i i^2 f - (2/3) sum f)/2 over the 3x3 grid, same for e.
  d = (sxx - 2.0 / 3.0 * sum) / 2.0;
  e = (syy - 2.0 / 3.0 * sum) / 2.0;
  // Stationary point: [2d g; g 2e] [x; y] = -[b; c]
  const double det = 4.0 * d * e - g * g;
  SubPixel out{static_cast<double>(r), static_cast<double>(c), f[1][1]};
  if (std::abs(det) < 1e-30) return out;
  const double x = (-b * 2.0 * e + cc * g) / det;
  const double y = (-cc * 2.0 * d + b * g) / det;
  if (std::abs(x) > 1.0 || std::abs(y) > 1.0) return out;
  out.d_row = r + x;
  out.d_col = c + y;
  return out;
}

/// The same on the surface `s` itself.
inline SubPixel fit_extremum_3x3(const cv::Mat& s, int r, int c) {
  return fit_extremum_3x3_of([&s](int dr, int dc) { return at_lag(s, dr, dc); }, r, c);
}

/// The spread of the first `n` values of `abs_values` (absolute values,
/// reordered): 1.4826 median, the standard deviation were they Gaussian,
/// robust to the few that stand out. 0 for n = 0.
template <class Array>
double median_spread(Array& abs_values, std::size_t n) {
  if (n == 0) return 0.0;
  const auto mid = abs_values.begin() + static_cast<std::ptrdiff_t>(n / 2);
  std::nth_element(abs_values.begin(), mid, abs_values.begin() + static_cast<std::ptrdiff_t>(n));
  return 1.4826 * *mid;
}

}  // namespace gvs::dsp::detail
