#include "gvs/daemon/frame_processor.hpp"

#include <cmath>

namespace gvs::daemon {

FrameProcessor::FrameProcessor(const FrameProcessorConfig& config)
    : config_(config), estimator_(dsp::make_estimator(config.estimator)) {}

void FrameProcessor::reset() noexcept {
  estimator_->reset();
  have_previous_ = false;
}

dsp::VelocityEstimate FrameProcessor::reject(const dsp::FrameView& frame, const char* reason) noexcept {
  ++rejects_.unreadable;
  const std::int64_t mid_t_ns = dsp::mid_exposure_ns(frame.t_ns, frame.exposure);
  return dsp::no_estimate(frame.index, mid_t_ns, reason);
}

dsp::VelocityEstimate FrameProcessor::process(const dsp::FrameView& frame) {
  const dsp::CameraGeometry& cam = config_.estimator.camera;
  const std::int64_t mid_t_ns = dsp::mid_exposure_ns(frame.t_ns, frame.exposure);
  if (frame.gray.empty() || frame.gray.type() != CV_8UC1 || frame.gray.cols != cam.width_px ||
      frame.gray.rows != cam.height_px) {
    ++rejects_.wrong_size;
    return dsp::no_estimate(frame.index, mid_t_ns, "wrong-size");
  }
  const double exposure_us = frame.exposure.exposure_us;
  const double lit_us = frame.exposure.lit_time_us();
  if (!(exposure_us > 0.0) || !(lit_us > 0.0) || exposure_us > config_.max_exposure_us ||
      !std::isfinite(exposure_us)) {
    ++rejects_.bad_exposure;
    return dsp::no_estimate(frame.index, mid_t_ns, "bad-exposure");
  }
  if (have_previous_) {
    if (frame.t_ns <= previous_t_ns_) {
      // Time went backwards: the pair history is meaningless. Start again
      // from this frame, but do not measure it against the old one.
      ++rejects_.time_backwards;
      estimator_->reset();
      previous_t_ns_ = frame.t_ns;
      (void)estimator_->estimate(frame);
      return dsp::no_estimate(frame.index, mid_t_ns, "time-backwards");
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
