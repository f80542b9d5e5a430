#include "gvs/dsp/frame_processor.hpp"

#include <cmath>

#include "gvs/core/geometry.hpp"
#include "gvs/dsp/ground_plane.hpp"

namespace gvs::dsp {

FrameProcessor::FrameProcessor(const FrameProcessorConfig& config)
    : config_(config), estimator_(make_estimator(config.estimator)) {
  if (config.lasers.enabled()) {
    const core::CameraGeometry& cam = config.estimator.camera;
    finder_ = std::make_unique<LaserDotFinder>(cam, config.nominal_height_mm, config.lasers);
    masked_.create(cam.height_px, cam.width_px, CV_8UC1);
  }
}

namespace {

/// Scales the estimate's velocity with the measured ground
/// (gvs/dsp/ground_plane.hpp, point 3) and says so.
void apply_ride(const core::RideHeight& ride, double nominal_height_mm, bool correct, core::VelocityEstimate& e) {
  e.ride = ride;
  if (!ride.has_height || !correct) return;
  e.scale_source = core::ScaleSource::laser_dots;
  if (!e.has_speed) return;
  if (e.has_velocity_xy()) {
    correct_velocity(ride, nominal_height_mm, e.vx_mps, e.vy_mps);
    e.speed_mps = std::hypot(e.vx_mps, e.vy_mps);
    if (e.has_direction) e.direction_deg = core::direction_deg({e.vx_mps, e.vy_mps});
  } else {
    e.speed_mps *= ride.height_mm / nominal_height_mm;
  }
}

}  // namespace

void FrameProcessor::reset() noexcept {
  estimator_->reset();
  if (finder_) finder_->forget();
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
  // The dots move with the height, not with the ground: find them, then
  // hide them from the estimator. They are found in the copy the mask goes
  // into (the same pixels): one pass over the camera's buffer in order
  // brings the frame into the cache for the tracks' scattered reads.
  core::FrameView view = frame;
  if (finder_) {
    dots_ = finder_->find_and_mask(frame.gray, masked_, core::mid_exposure_ns(frame.t_ns, frame.exposure),
                                   frame.exposure.exposure_us);
    view.gray = masked_;
  }
  if (have_previous_) {
    if (frame.t_ns <= previous_t_ns_) {
      // Time went backwards: the pair history is meaningless. Start again
      // from this frame, but do not measure it against the old one.
      estimator_->reset();
      previous_t_ns_ = frame.t_ns;
      (void)estimator_->estimate(view);
      return reject(frame, RejectReason::time_backwards);
    }
    if (static_cast<double>(frame.t_ns - previous_t_ns_) * 1e-9 > config_.max_gap_s) {
      ++rejects_.time_gap;
      estimator_->reset();
    }
  }
  have_previous_ = true;
  previous_t_ns_ = frame.t_ns;
  core::VelocityEstimate e = estimator_->estimate(view);
  if (finder_) apply_ride(dots_.ride, config_.nominal_height_mm, config_.correct_scale, e);
  return e;
}

}  // namespace gvs::dsp
