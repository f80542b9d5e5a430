#include "gvs/dsp/fine_texture.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>

namespace gvs::dsp {

FineTexture measure_fine_texture(const cv::Mat& gray) {
  FineTexture out;
  if (gray.empty() || gray.type() != CV_8UC1 || gray.rows < 8 || gray.cols < 8) return out;
  // Steps (d_row, d_col): along a row, down a column, and the two diagonals.
  constexpr std::array<std::array<int, 2>, 4> kSteps{{{0, 1}, {1, 0}, {1, 1}, {1, -1}}};
  // Sums of squared grey-level steps in integers: exact, as in double.
  std::array<std::int64_t, 4> d1{};
  std::array<std::int64_t, 4> d2{};
  std::int64_t n = 0;
  for (int r = 2; r + 4 < gray.rows; r += 2) {
    const std::uint8_t* row[5];
    for (int k = 0; k < 5; ++k) row[k] = gray.ptr<std::uint8_t>(r + k);
    for (int c = 4; c + 4 < gray.cols; c += 2) {
      const int g0 = row[0][c];
      for (std::size_t s = 0; s < kSteps.size(); ++s) {
        const int dr = kSteps[s][0];
        const int dc = kSteps[s][1];
        const int e1 = row[dr][c + dc] - g0;
        const int e2 = row[2 * dr][c + 2 * dc] - g0;
        d1[s] += e1 * e1;
        d2[s] += e2 * e2;
      }
      ++n;
    }
  }
  if (n == 0) return out;
  const double nn = static_cast<double>(n);
  std::array<double, 4> t{};
  double d1_sum = 0.0;
  for (std::size_t s = 0; s < t.size(); ++s) {
    t[s] = (static_cast<double>(d2[s]) - static_cast<double>(d1[s])) / nn;
    d1_sum += static_cast<double>(d1[s]) / nn;
  }
  // Quadratic form: T(u) = a u_x^2 + 2 b u_x u_y + c u_y^2 (x along a row).
  // The diagonal steps are sqrt(2) long: T(1,1) - T(1,-1) = 4 b.
  const double a = t[0];
  const double c = t[1];
  const double b = (t[2] - t[3]) / 4.0;
  const double mean = 0.5 * (a + c);
  const double half_gap = std::hypot(0.5 * (a - c), b);
  out.weakest_grey2 = mean - half_gap;
  out.strongest_grey2 = mean + half_gap;
  out.difference_grey2 = d1_sum / 4.0;
  const auto [t_min, t_max] = std::minmax_element(t.begin(), t.end());
  out.step_min_over_max = *t_max > 0.0 ? std::max(*t_min, 0.0) / *t_max : 0.0;
  return out;
}

}  // namespace gvs::dsp
