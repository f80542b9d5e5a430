// Frame statistics and the "nothing to measure" verdicts.
#include "gvs/dsp/frame_check.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace gvs::dsp {

FrameStats measure_frame(const cv::Mat& gray) {
  FrameStats s;
  if (gray.empty() || gray.type() != CV_8UC1) return s;
  double sum = 0.0;
  double sum_sq = 0.0;
  double sum_all = 0.0;
  std::int64_t n = 0;
  std::int64_t n_sat = 0;
  std::int64_t n_all = 0;
  for (int r = 0; r < gray.rows; r += 2) {
    const std::uint8_t* row = gray.ptr<std::uint8_t>(r);
    for (int c = 0; c < gray.cols; c += 2) {
      const double g = row[c];
      sum_all += g;
      ++n_all;
      if (row[c] == 255) {
        ++n_sat;
        continue;
      }
      sum += g;
      sum_sq += g * g;
      ++n;
    }
  }
  if (n_all == 0) return s;
  s.mean_grey = sum_all / static_cast<double>(n_all);
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
