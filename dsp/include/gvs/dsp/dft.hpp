// The discrete Fourier transform, planned once.
//
// Same arithmetic as cv::dft (OpenCV's own mixed-radix FFT), but cv::dft
// builds its plan (twiddle factors, work buffers) on every call, which
// allocates. A DftPlan builds it on its first run and reuses it while the
// size stays the same, so every later run allocates nothing: what the
// daemon's processing thread needs.
#pragma once

#include <opencv2/core/hal/hal.hpp>
#include <opencv2/core/mat.hpp>

namespace gvs::dsp {

class DftPlan {
 public:
  enum class Direction {
    forward_real_to_complex,  ///< CV_32FC1 image -> CV_32FC2 full complex spectrum
    inverse_complex_to_real,  ///< CV_32FC2 spectrum -> CV_32FC1, scaled by 1/(rows cols)
  };

  explicit DftPlan(Direction direction) : direction_(direction) {}

  /// out = DFT(in) (or its scaled inverse). `out` is created on the first run
  /// (and again only if the size changes); so is the plan.
  void run(const cv::Mat& in, cv::Mat& out);

 private:
  Direction direction_;
  cv::Size planned_size_;
  bool planned_continuous_ = false;
  cv::Ptr<cv::hal::DFT2D> plan_;
};

}  // namespace gvs::dsp
