// Standstill: the previous frame and this one show the same ground, unmoved.
#include <algorithm>
#include <array>
#include <cstdint>

#include "gvs/dsp/fine_texture.hpp"
#include "gvs/dsp/gvs_analysis.hpp"

namespace gvs::dsp {

namespace {

bool ground_is_sharp(const FineTexture& t, const GvsEstimatorSettings& set) {
  return t.isotropy() >= set.still_min_isotropy && t.step_min_over_max >= set.still_min_step_ratio &&
         t.weakest_over_difference() >= set.still_min_fine_texture;
}

/// mean((h1 - k h0)^2) / (2 mean(h1^2)) over every second row and column,
/// where h is the frame less its mean over each kBlockPx x kBlockPx block.
double detrended_difference_ratio(const cv::Mat& gray, const cv::Mat& previous, double k) {
  // The light's fall-off (and any shading smooth across the frame) is the
  // same in both frames whether the ground moved or not. On low-contrast
  // ground it is most of a frame's variance: torcs_etrack2 at 0.1 mm per
  // photo pixel, 3 ms at 1 m/s (30 px streaks, frames 167 px apart), reads
  // 0.09 with it (alike) and 0.68 without; standing frames of every
  // photograph and light level read 0.002-0.04 without it. Steps between
  // pixels and stones up to the block's size stay.
  //
  // One pass of whole-number sums per block: with n samples, sums S1, S0
  // of the two frames' grey levels and S11, S00, S10 of their products,
  //   n sum (h1 - k h0)^2 = V11 - 2 k V10 + k^2 V00,   n sum h1^2 = V11,
  // where V11 = n S11 - S1^2, V10 = n S10 - S1 S0, V00 = n S00 - S0^2 are
  // exact in 64-bit integers (a block holds at most 64 samples).
  constexpr int kBlockPx = 16;
  constexpr int kMaxBlocks = 256;  // 4096 px wide
  struct BlockSums {
    std::int64_t n, s1, s0, s11, s00, s10;
  };
  const int blocks = std::min((gray.cols + kBlockPx - 1) / kBlockPx, kMaxBlocks);
  std::array<BlockSums, kMaxBlocks> sums{};
  double diff_sq = 0.0;
  double power = 0.0;
  for (int band = 0; band < gray.rows; band += kBlockPx) {
    const int band_end = std::min(band + kBlockPx, gray.rows - 1);  // r + 1 < rows, as check_still
    std::fill(sums.begin(), sums.begin() + blocks, BlockSums{});
    for (int r = band; r < band_end; r += 2) {
      const auto* g1 = gray.ptr<std::uint8_t>(r);
      const auto* g0 = previous.ptr<std::uint8_t>(r);
      for (int b = 0; b < blocks; ++b) {
        BlockSums& bs = sums[static_cast<std::size_t>(b)];
        const int c_end = std::min((b + 1) * kBlockPx, gray.cols - 1);  // c + 1 < cols
        for (int c = b * kBlockPx; c < c_end; c += 2) {
          const std::int64_t a1 = g1[c];
          const std::int64_t a0 = g0[c];
          bs.n += 1;
          bs.s1 += a1;
          bs.s0 += a0;
          bs.s11 += a1 * a1;
          bs.s00 += a0 * a0;
          bs.s10 += a1 * a0;
        }
      }
    }
    for (int b = 0; b < blocks; ++b) {
      const BlockSums& bs = sums[static_cast<std::size_t>(b)];
      if (bs.n == 0) continue;
      const auto v11 = static_cast<double>(bs.n * bs.s11 - bs.s1 * bs.s1);
      const auto v10 = static_cast<double>(bs.n * bs.s10 - bs.s1 * bs.s0);
      const auto v00 = static_cast<double>(bs.n * bs.s00 - bs.s0 * bs.s0);
      const auto n = static_cast<double>(bs.n);
      diff_sq += (v11 - 2.0 * k * v10 + k * k * v00) / n;
      power += v11 / n;
    }
  }
  return power > 0.0 ? diff_sq / (2.0 * power) : 1e9;
}

}  // namespace

StillCheck check_still(const cv::Mat& gray, double mean_grey, const PreviousFrame& previous,
                       const GvsEstimatorSettings& set) {
  // ratio = mean((h1 - k h0)^2) / (2 mean(h1^2)), k = mean1/mean0 (exposure
  // may change), h a frame less its smooth light (detrended_difference_ratio).
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
  // Sums of products of whole grey levels in integers: exact, as in double.
  std::int64_t sum_i = 0;
  std::int64_t sum_sq_i = 0;
  std::int64_t sum_right_i = 0;  // sum of g(r,c) g(r,c+1)
  std::int64_t sum_down_i = 0;   // sum of g(r,c) g(r+1,c)
  std::int64_t n = 0;
  for (int r = 0; r + 1 < gray.rows; r += 2) {
    const auto* g1 = gray.ptr<std::uint8_t>(r);
    const auto* below = gray.ptr<std::uint8_t>(r + 1);
    for (int c = 0; c + 1 < gray.cols; c += 2) {
      ++n;
      const std::int64_t a = g1[c];
      sum_i += a;
      sum_sq_i += a * a;
      sum_right_i += a * g1[c + 1];
      sum_down_i += a * below[c];
    }
  }
  const double nn = static_cast<double>(n);
  const auto sum = static_cast<double>(sum_i);
  const auto sum_sq = static_cast<double>(sum_sq_i);
  const auto sum_right = static_cast<double>(sum_right_i);
  const auto sum_down = static_cast<double>(sum_down_i);
  const double mean = sum / nn;
  const double var = sum_sq / nn - mean * mean;
  if (var <= 0.0) return check;
  check.ratio = detrended_difference_ratio(gray, previous.gray, k);
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
