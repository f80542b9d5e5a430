// Frame statistics and the "nothing to measure" verdicts.
#include "gvs/dsp/frame_check.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace gvs::dsp {

FrameStats measure_frame(const cv::Mat& gray) {
  FrameStats s;
  if (gray.empty() || gray.type() != CV_8UC1) return s;
  // Sums of whole grey levels in integers: exact (as the same sums in
  // double are), and without a chain of dependent floating-point adds.
  std::int64_t sum_all = 0;
  std::int64_t sum_sq_all = 0;
  std::int64_t n_sat = 0;
  std::int64_t n_all = 0;
  for (int r = 0; r < gray.rows; r += 2) {
    const std::uint8_t* row = gray.ptr<std::uint8_t>(r);
    for (int c = 0; c < gray.cols; c += 2) {
      const std::int64_t g = row[c];
      sum_all += g;
      sum_sq_all += g * g;
      n_sat += g == 255 ? 1 : 0;
      ++n_all;
    }
  }
  if (n_all == 0) return s;
  // The contrast leaves the saturated pixels out.
  const std::int64_t n = n_all - n_sat;
  const auto sum = static_cast<double>(sum_all - 255 * n_sat);
  const auto sum_sq = static_cast<double>(sum_sq_all - 255 * 255 * n_sat);
  s.mean_grey = static_cast<double>(sum_all) / static_cast<double>(n_all);
  s.saturated_fraction = static_cast<double>(n_sat) / static_cast<double>(n_all);
  if (n > 1) {
    const double m = sum / static_cast<double>(n);
    s.contrast_grey = std::sqrt(std::max(0.0, sum_sq / static_cast<double>(n) - m * m));
  }
  return s;
}

std::optional<Method> frame_problem(const FrameStats& stats, const FrameCheckLimits& limits) {
  if (stats.saturated_fraction > limits.max_saturated_fraction) return Method::saturated;
  if (stats.mean_grey < limits.dark_mean_grey) return Method::dark;
  if (stats.contrast_grey < limits.min_contrast_grey) {
    return stats.mean_grey < 4.0 * limits.dark_mean_grey ? Method::dark : Method::no_texture;
  }
  return std::nullopt;
}

}  // namespace gvs::dsp
