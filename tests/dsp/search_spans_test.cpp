// The spans a search visits (dsp/src/gvs/search_spans.hpp) against a full
// scan with the same test: every lag or bin the scan accepts is visited, in
// the scan's order, and the spans are not the whole row.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "gvs/dsp/dft.hpp"
#include "gvs/dsp/spectrum.hpp"
#include "search_spans.hpp"

namespace gvs::dsp {
namespace {

TEST(SearchSpans, RingSpanHoldsExactlyTheLagsAFullScanAccepts) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> radius(0.0, 60.0);
  std::uniform_int_distribution<int> lag(-70, 70);
  std::uniform_int_distribution<int> limit(0, 80);
  for (int trial = 0; trial < 5000; ++trial) {
    const double inner = trial % 7 == 0 ? std::floor(radius(rng)) : radius(rng);  // whole radii hit the edges
    const double outer = inner + radius(rng);
    const bool closed = trial % 2 == 0;
    const int dr = lag(rng);
    const int lim = limit(rng);
    std::vector<int> scan;
    for (int a = 0; a <= lim; ++a) {
      const auto d2 = static_cast<double>(dr * dr + a * a);
      const bool in = (closed ? d2 >= inner * inner : d2 > inner * inner) && d2 <= outer * outer;
      if (in) scan.push_back(a);
    }
    const detail::ColumnSpan s = detail::ring_span(dr, inner, closed, outer, lim);
    std::vector<int> span;
    for (int a = s.lo; a <= s.hi; ++a) span.push_back(a);
    ASSERT_EQ(span, scan) << "dr " << dr << " inner " << inner << (closed ? " (closed)" : "") << " outer "
                          << outer << " limit " << lim;
  }
}

TEST(SearchSpans, StripColumnsHoldEveryBinOfTheStripInColumnOrder) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> angle(0.0, 2.0 * kPi);
  std::uniform_real_distribution<double> width(0.01, 0.4);
  for (int trial = 0; trial < 3000; ++trial) {
    const int cols = trial % 3 == 0 ? 385 : 512;
    const int rows = 384;
    const std::vector<double> k_row = angular_frequencies(rows);
    const std::vector<double> k_col = angular_frequencies(cols);
    // Axes exactly along a row or a column too (u_col = 0 or u_row = 0).
    const double theta = trial % 50 == 0 ? 0.0 : trial % 50 == 1 ? kPi / 2.0 : angle(rng);
    const double u_row = std::sin(theta);
    const double u_col = std::cos(theta);
    const double h = width(rng);
    const double kr = k_row[static_cast<std::size_t>(trial % rows)];
    std::vector<int> strip;
    for (int c = 0; c < cols; ++c) {
      if (std::abs(kr * u_row + k_col[static_cast<std::size_t>(c)] * u_col) <= h) strip.push_back(c);
    }
    const detail::StripColumns s = detail::strip_columns(cols, kr * u_row, u_col, h);
    std::vector<int> visited;
    for (int run = 0; run < 2; ++run) {
      for (int c = s.begin[run]; c < s.end[run]; ++c) visited.push_back(c);
    }
    for (std::size_t i = 1; i < visited.size(); ++i) ASSERT_LT(visited[i - 1], visited[i]) << "column order";
    std::size_t j = 0;
    for (const int c : strip) {
      while (j < visited.size() && visited[j] < c) ++j;
      ASSERT_TRUE(j < visited.size() && visited[j] == c) << "column " << c << " of the strip not visited";
    }
    // At most a column more at each end of each run, unless the strip is
    // (nearly) parallel to the rows and the whole row may be in it.
    if (std::abs(u_col) > 1e-6) {
      EXPECT_LE(visited.size(), strip.size() + 4) << "theta " << theta;
    }
  }
}

// Sums over the half spectrum, each bin counted for itself and its mirror,
// against sums over the full spectrum of the same frame (DftPlan's mirrored
// output): the moments streak_axis() and refine_axis() take, over the whole
// spectrum and over strips, with even and odd widths.
TEST(SearchSpans, HalfSpectrumSumsEqualTheFullSpectrums) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> grey(0.0f, 255.0f);
  std::uniform_real_distribution<double> angle(0.0, 2.0 * kPi);
  for (const cv::Size size : {cv::Size(64, 48), cv::Size(65, 48), cv::Size(64, 47)}) {
    cv::Mat frame(size, CV_32F);
    for (int r = 0; r < size.height; ++r) {
      for (int c = 0; c < size.width; ++c) frame.at<float>(r, c) = grey(rng);
    }
    cv::Mat full;
    cv::Mat half;
    DftPlan(DftPlan::Direction::forward_real_to_complex, size).run(frame, full);
    DftPlan(DftPlan::Direction::forward_real_to_half_complex, size).run(frame, half);
    const std::vector<double> k_row = angular_frequencies(size.height);
    const std::vector<double> k_col = angular_frequencies(size.width);
    for (int trial = 0; trial < 20; ++trial) {
      const double theta = angle(rng);
      const double u_row = std::sin(theta);
      const double u_col = std::cos(theta);
      const double h = trial == 0 ? 10.0 : 0.3;  // the first: every bin
      double full_rc = 0.0;
      double half_rc = 0.0;
      double full_p = 0.0;
      double half_p = 0.0;
      for (int r = 0; r < size.height; ++r) {
        // The row k_row = -pi (even heights) is its own mirror with k_col
        // negated, so f must be even in k_col there too; the estimator's
        // sums weigh it 0 (its band ends at 2.6 rad/px).
        if (2 * r == size.height) continue;
        const double kr = k_row[static_cast<std::size_t>(r)];
        const auto in_strip = [&](int c) { return std::abs(kr * u_row + k_col[static_cast<std::size_t>(c)] * u_col) <= h; };
        for (int c = 0; c < size.width; ++c) {
          const auto& x = full.at<cv::Vec2f>(r, c);
          if (!in_strip(c)) continue;
          const double p = static_cast<double>(x[0] * x[0] + x[1] * x[1]);
          full_p += p;
          full_rc += p * kr * k_col[static_cast<std::size_t>(c)];
        }
        const detail::StripColumns s = detail::strip_columns(size.width, kr * u_row, u_col, h);
        detail::for_each_half_power(half, r, s, [&](int c, float power, double m) {
          if (!in_strip(c)) return;
          half_p += m * static_cast<double>(power);
          half_rc += m * static_cast<double>(power) * kr * k_col[static_cast<std::size_t>(c)];
        });
      }
      ASSERT_GT(full_p, 0.0);
      EXPECT_NEAR(half_p, full_p, 1e-9 * full_p) << size.width << "x" << size.height << " theta " << theta << " h " << h;
      EXPECT_NEAR(half_rc, full_rc, 1e-9 * full_p * kPi * kPi) << size.width << "x" << size.height << " theta " << theta << " h " << h;
    }
  }
}

}  // namespace
}  // namespace gvs::dsp
