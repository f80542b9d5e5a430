#include "gvs/dsp/frame_processor.hpp"

#include <cmath>

namespace gvs::dsp {

FrameProcessor::FrameProcessor(const FrameProcessorConfig& config)
    : config_(config), estimator_(make_estimator(config.estimator)) {}

void FrameProcessor::reset() noexcept {
  estimator_->reset();
  have_previous_ = false;
}

core::VelocityEstimate FrameProcessor::reject(const core::FrameView& frame, RejectReason reason) noexcept {
  ++rejects_.by_reason[static_cast<std::size_t>(reason)];
  return core::no_estimate(frame.index, core::mid_exposure_ns(frame.t_ns, frame.exposure), reject_method(reason));
}

core::VelocityEstimate FrameProcessor::process(const core::FrameView& frame) {
  const core::CameraGeometry& cam = config_.estimator.camera;
  if (frame.gray.empty() || frame.gray.type() != CV_8UC1 || frame.gray.cols != cam.width_px ||
      frame.gray.rows != cam.height_px) {
    return reject(frame, RejectReason::wrong_size);
  }
  const double exposure_us = frame.exposure.exposure_us;
  const double lit_us = frame.exposure.lit_time_us();
  if (!(exposure_us > 0.0) || !(lit_us > 0.0) || exposure_us > config_.max_exposure_us ||
      !std::isfinite(exposure_us)) {
    return reject(frame, RejectReason::bad_exposure);
  }
  if (have_previous_) {
    if (frame.t_ns <= previous_t_ns_) {
      // Time went backwards: the pair history is meaningless. Start again
      // from this frame, but do not measure it against the old one.
      estimator_->reset();
      previous_t_ns_ = frame.t_ns;
      (void)estimator_->estimate(frame);
      return reject(frame, RejectReason::time_backwards);
    }
    if (static_cast<double>(frame.t_ns - previous_t_ns_) * 1e-9 > config_.max_gap_s) {
      ++rejects_.time_gap;
      estimator_->reset();
    }
  }
  have_previous_ = true;
  previous_t_ns_ = frame.t_ns;
  return estimator_->estimate(frame);
}

}  // namespace gvs::dsp
