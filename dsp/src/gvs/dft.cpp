// DftPlan (see dft.hpp): cv::dft's own steps (OpenCV 4.6, core/src/dxt.cpp,
// cv::dft) with the hal::DFT2D plan kept between calls.
#include "gvs/dsp/dft.hpp"

namespace gvs::dsp {

void DftPlan::run(const cv::Mat& in, cv::Mat& out) {
  const bool forward = direction_ == Direction::forward_real_to_complex;
  out.create(in.size(), forward ? CV_32FC2 : CV_32FC1);
  const bool continuous = in.isContinuous() && out.isContinuous();
  if (plan_.empty() || in.size() != planned_size_ || continuous != planned_continuous_) {
    int flags = continuous ? CV_HAL_DFT_IS_CONTINUOUS : 0;
    if (!forward) flags |= CV_HAL_DFT_INVERSE | CV_HAL_DFT_SCALE;
    // One channel in, two out: real to full complex; two in, one out: complex to real.
    plan_ = cv::hal::DFT2D::create(in.cols, in.rows, CV_32F, forward ? 1 : 2, forward ? 2 : 1, flags, 0);
    planned_size_ = in.size();
    planned_continuous_ = continuous;
  }
  plan_->apply(in.data, in.step, out.data, out.step);
}

}  // namespace gvs::dsp
