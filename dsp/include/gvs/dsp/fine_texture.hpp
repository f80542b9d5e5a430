// Fine texture of a frame in every direction: the evidence that the ground is
// sharp (not smeared by motion) before two alike frames may mean standstill.
#pragma once

#include <algorithm>

#include <opencv2/core/mat.hpp>

namespace gvs::dsp {

/// Fine-texture power of a frame along its weakest and strongest direction,
/// with the white part (temporal noise, the sensor's pixel offsets and
/// column offsets) and the smooth part (the ring light's fall-off) left out.
///
/// Directional difference power at lag l along the unit step u:
///   D_l(u) = mean over p of (g(p + l u) - g(p))^2.
/// A white component adds 2 sigma^2 at every lag; ground texture seen
/// through the lens is correlated over a few pixels, so its D grows with the
/// lag. T(u) = D_2(u) - D_1(u) keeps the texture and drops the white part
/// (the column pattern is white across columns and cancels down them). The
/// light's fall-off adds 3 (grad F . u)^2, a few hundredths of a grey level
/// squared: far below any texture worth the name.
///
/// A frame blurred by motion along u keeps its texture across u and loses it
/// along u, so T(u) -> 0 there. T over the four steps (0, 1), (1, 0), (1, 1),
/// (1, -1) fits the quadratic form [a b; b c] (the structure tensor of the
/// texture): a = T(0,1), c = T(1,0), b = (T(1,1) - T(1,-1)) / 4, whose
/// eigenvalues are the weakest and strongest directional powers. The
/// diagonal steps are sqrt(2) long and, on a grain of about a pixel, reach
/// past it, so the fit sees less texture across a diagonal streak than
/// there is; the smallest of the four T over the largest is ~0 for a streak
/// along any of the four steps, and checks it.
struct FineTexture {
  double weakest_grey2 = 0.0;     ///< texture power along the direction with the least
  double strongest_grey2 = 0.0;   ///< ... and with the most
  double difference_grey2 = 0.0;  ///< mean lag-1 difference power D_1 (texture and white part)
  double step_min_over_max = 0.0; ///< smallest of the four T(u) over the largest

  /// weakest / strongest: ~1 for sharp isotropic ground, -> 0 when smeared along one direction.
  [[nodiscard]] double isotropy() const {
    return strongest_grey2 > 0.0 ? std::max(weakest_grey2, 0.0) / strongest_grey2 : 0.0;
  }
  /// weakest / D_1: how much of the pixel-to-pixel difference is texture in the weakest direction.
  [[nodiscard]] double weakest_over_difference() const {
    return difference_grey2 > 0.0 ? std::max(weakest_grey2, 0.0) / difference_grey2 : 0.0;
  }
};

/// Measures an 8-bit frame (CV_8UC1) on every second row and column. No
/// allocation.
FineTexture measure_fine_texture(const cv::Mat& gray);

}  // namespace gvs::dsp
