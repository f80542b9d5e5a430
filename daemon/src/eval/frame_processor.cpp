#include "gvs/daemon/frame_processor.hpp"

#include <cmath>

namespace gvs::daemon {

namespace {

std::int64_t light_centre_ns(const dsp::FrameView& frame) noexcept {
  return frame.t_ns + static_cast<std::int64_t>(std::llround(frame.exposure.light_centre_us() * 1000.0));
}

}  // namespace

FrameProcessor::FrameProcessor(const FrameProcessorConfig& config)
    : config_(config), estimator_(dsp::make_estimator(config.estimator)) {}

void FrameProcessor::reset() noexcept {
  estimator_->reset();
  have_previous_ = false;
}

dsp::VelocityEstimate FrameProcessor::reject(const dsp::FrameView& frame, RejectReason reason) noexcept {
  ++rejects_.by_reason[static_cast<std::size_t>(reason)];
  return dsp::no_estimate(frame.index, light_centre_ns(frame), reject_method(reason));
}

dsp::VelocityEstimate FrameProcessor::process(const dsp::FrameView& frame) noexcept {
  const dsp::CameraGeometry& cam = config_.estimator.camera;
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

}  // namespace gvs::daemon
