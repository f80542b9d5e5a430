// Standstill: the previous frame and this one show the same ground, unmoved.
#include <algorithm>
#include <cstdint>

#include "gvs/dsp/fine_texture.hpp"
#include "gvs/dsp/gvs_analysis.hpp"

namespace gvs::dsp {

namespace {

bool ground_is_sharp(const FineTexture& t, const GvsEstimatorSettings& set) {
  return t.isotropy() >= set.still_min_isotropy && t.step_min_over_max >= set.still_min_step_ratio &&
         t.weakest_over_difference() >= set.still_min_fine_texture;
}

}  // namespace

StillCheck check_still(const cv::Mat& gray, double mean_grey, const PreviousFrame& previous,
                       const GvsEstimatorSettings& set) {
  // ratio = mean((g1 - k g0)^2) / (2 var(g1)), k = mean1/mean0 (exposure may change).
  // Identical texture: only temporal noise is left (fixed-pattern noise cancels).
  //
  // But a frame that is only fixed-pattern noise (texture smeared flat by a
  // streak much longer than the frame, e.g. under-exposed at speed) repeats
  // too. The asphalt seen through the lens is smooth over neighbouring pixels
  // in both directions; the sensor's pattern is not (pixel offsets are white,
  // column offsets are smooth only down a column). So the frame must also be
  // correlated with its right and its lower neighbour:
  //   rho = cov(g(r,c), g(r,c+1)) / var(g), the same for (r+1,c); min >= still_min_neighbour_corr.
  StillCheck check;
  const double k = previous.mean_grey > 0.0 ? mean_grey / previous.mean_grey : 1.0;
  double diff_sq = 0.0;
  double sum = 0.0;
  double sum_sq = 0.0;
  double sum_right = 0.0;  // sum of g(r,c) g(r,c+1)
  double sum_down = 0.0;   // sum of g(r,c) g(r+1,c)
  std::int64_t n = 0;
  for (int r = 0; r + 1 < gray.rows; r += 2) {
    const auto* g1 = gray.ptr<std::uint8_t>(r);
    const auto* below = gray.ptr<std::uint8_t>(r + 1);
    const auto* g0 = previous.gray.ptr<std::uint8_t>(r);
    for (int c = 0; c + 1 < gray.cols; c += 2) {
      const double a = g1[c];
      const double d = a - k * g0[c];
      diff_sq += d * d;
      sum += a;
      sum_sq += a * a;
      sum_right += a * g1[c + 1];
      sum_down += a * below[c];
      ++n;
    }
  }
  const double nn = static_cast<double>(n);
  const double mean = sum / nn;
  const double var = sum_sq / nn - mean * mean;
  if (var <= 0.0) return check;
  check.ratio = diff_sq / nn / (2.0 * var);
  const double rho_right = (sum_right / nn - mean * mean) / var;
  const double rho_down = (sum_down / nn - mean * mean) / var;
  if (check.ratio >= set.still_ratio || std::min(rho_right, rho_down) < set.still_min_neighbour_corr) {
    return check;
  }
  // Alike is not unmoved: two frames smeared by a streak longer than the
  // frame are alike too (each pixel averages centimetres of ground, cracks
  // along the motion stay put, and the fixed pattern and the light's
  // fall-off are the same in both). Standstill needs both frames sharp: fine
  // texture in every direction, well above the sensor's white part.
  check.still = ground_is_sharp(measure_fine_texture(gray), set) &&
                ground_is_sharp(measure_fine_texture(previous.gray), set);
  return check;
}

}  // namespace gvs::dsp
