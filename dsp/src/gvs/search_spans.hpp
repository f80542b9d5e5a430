// The parts of a spectrum or a correlation surface a search visits: only
// those a full scan's test could accept, in the order a full scan visits
// them, so a sum or a maximum over them equals the full scan's exactly;
// and a spectrum's power read from its non-redundant half.
#pragma once

#include <algorithm>
#include <cmath>
#include <type_traits>

#include <opencv2/core/mat.hpp>

#include "gvs/dsp/vocabulary.hpp"

namespace gvs::dsp::detail {

/// |dc| from `lo` to `hi` (empty when lo > hi).
struct ColumnSpan {
  int lo = 0;
  int hi = -1;
  [[nodiscard]] bool empty() const { return lo > hi; }
};

/// The columns of row lag `dr` in the ring inner < |d| <= outer (or
/// inner <= |d| with `inner_closed`), |dc| at most `limit`: the two arcs a
/// search ring cuts from the row, found from d^2 = dr^2 + dc^2 as a full
/// scan's test would find them (the same comparisons in double).
inline ColumnSpan ring_span(int dr, double inner_px, bool inner_closed, double outer_px, int limit) {
  const double in2 = inner_px * inner_px;
  const double out2 = outer_px * outer_px;
  const auto d2 = [dr](int a) { return static_cast<double>(dr * dr + a * a); };
  ColumnSpan s;
  int hi = std::min(limit, static_cast<int>(std::sqrt(std::max(0.0, out2 - dr * dr))));
  while (hi < limit && d2(hi + 1) <= out2) ++hi;
  while (hi >= 0 && d2(hi) > out2) --hi;
  const auto inside_inner = [&](int a) { return inner_closed ? d2(a) >= in2 : d2(a) > in2; };
  int lo = std::max(0, static_cast<int>(std::sqrt(std::max(0.0, in2 - dr * dr))) - 1);
  while (lo > 0 && inside_inner(lo - 1)) --lo;
  while (lo <= hi && !inside_inner(lo)) ++lo;
  s.lo = lo;
  s.hi = hi;
  return s;
}

/// The columns of a spectrum row that can lie in the strip |a + k_col b| <= h
/// around a line k.u = 0 (a = k_row u_row, b = u_col): up to two runs of c,
/// in column order, each a column wider at both ends than the exact bounds.
/// The caller still tests every bin, so a sum over them equals the sum over
/// the whole row, at a tenth of the bins for a 0.2 rad/px strip.
struct StripColumns {
  int begin[2] = {0, 0};
  int end[2] = {0, 0};
};

inline StripColumns strip_columns(int cols, double a, double b, double h) {
  StripColumns s;
  const int j_first = (cols + 1) / 2 - cols;  // signed frequency index of the last column
  const int j_last = (cols + 1) / 2 - 1;
  const double per_column = 2.0 * kPi / cols;  // k_col = j 2 pi / cols
  double j_lo = static_cast<double>(j_first);
  double j_hi = static_cast<double>(j_last);
  if (std::abs(b) > 1e-9) {
    const double k1 = (-h - a) / b;
    const double k2 = (h - a) / b;
    j_lo = std::max(j_lo, std::floor(std::min(k1, k2) / per_column) - 1.0);
    j_hi = std::min(j_hi, std::ceil(std::max(k1, k2) / per_column) + 1.0);
  }
  if (j_lo > j_hi) return s;
  const int lo = static_cast<int>(j_lo);
  const int hi = static_cast<int>(j_hi);
  // j >= 0: columns j; j < 0: columns cols + j (the row's second half).
  if (hi >= 0) {
    s.begin[0] = std::max(lo, 0);
    s.end[0] = hi + 1;
  }
  if (lo < 0) {
    s.begin[1] = cols + lo;
    s.end[1] = cols + std::min(hi, -1) + 1;
  }
  return s;
}

/// f(c, |X(r, c)|^2, m) for c = begin .. end - 1 among the columns
/// 0 .. cols/2 the spectrum holds, in order; m is how many bins of the whole
/// spectrum the bin stands for: 2, its mirror X(-r, -c) = conj X(r, c)
/// lying past cols/2, or 1 in the columns 0 and cols/2 (even cols), which
/// hold their own mirrors. Summed over every row, m f equals the sum of f
/// over every bin for any f with f(-k) = f(k) (a moment k k^T, a ring of
/// |k|, a strip |k.u| <= h), read from the columns 0 .. cols/2 alone
/// (DftPlan, forward_real_to_half_complex), each bin once. (The row
/// k_row = -pi of an even height is its own mirror with k_col negated: f
/// must be even in k_col there too, or weigh it 0 as the band does.)
template <class F>
void for_each_half_power(const cv::Mat& spectrum, int r, int begin, int end, F&& f) {
  const int cols = spectrum.cols;
  const int last = cols / 2;  // the last column held
  const int stop = std::min(end, last + 1);
  const auto* x = spectrum.ptr<cv::Vec2f>(r);
  const auto power = [x](int c) { return x[c][0] * x[c][0] + x[c][1] * x[c][1]; };
  int c = std::max(begin, 0);
  if (c == 0 && c < stop) {
    f(0, power(0), 1.0);
    ++c;
  }
  const int interior_stop = cols % 2 == 0 ? std::min(stop, last) : stop;
  for (; c < interior_stop; ++c) f(c, power(c), 2.0);
  if (c == last && c < stop) f(c, power(c), 1.0);
}

/// for_each_half_power() with two lanes: f(c, |X(r, c)|^2, m, lane) where
/// lane (a std::integral_constant, 0 or 1) alternates between consecutive
/// interior columns, so that f can keep two sets of running sums whose adds
/// do not wait for each other (a sum in double over a row is otherwise one
/// add after another). The caller adds the lanes; the total differs from
/// one lane's only in rounding.
template <class F>
void for_each_half_power_2lanes(const cv::Mat& spectrum, int r, int begin, int end, F&& f) {
  constexpr std::integral_constant<std::size_t, 0> lane0{};
  constexpr std::integral_constant<std::size_t, 1> lane1{};
  const int cols = spectrum.cols;
  const int last = cols / 2;
  const int stop = std::min(end, last + 1);
  const auto* x = spectrum.ptr<cv::Vec2f>(r);
  const auto power = [x](int c) { return x[c][0] * x[c][0] + x[c][1] * x[c][1]; };
  int c = std::max(begin, 0);
  if (c == 0 && c < stop) {
    f(0, power(0), 1.0, lane0);
    ++c;
  }
  const int interior_stop = cols % 2 == 0 ? std::min(stop, last) : stop;
  for (; c + 1 < interior_stop; c += 2) {
    f(c, power(c), 2.0, lane0);
    f(c + 1, power(c + 1), 2.0, lane1);
  }
  if (c < interior_stop) {
    f(c, power(c), 2.0, lane0);
    ++c;
  }
  if (c == last && c < stop) f(c, power(c), 1.0, lane1);
}

/// for_each_half_power() over the strip_columns() of a row: the columns
/// of both runs that the half spectrum holds.
template <class F>
void for_each_half_power(const cv::Mat& spectrum, int r, const StripColumns& columns, F&& f) {
  for (int run = 0; run < 2; ++run) for_each_half_power(spectrum, r, columns.begin[run], columns.end[run], f);
}

}  // namespace gvs::dsp::detail
