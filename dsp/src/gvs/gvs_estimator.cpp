// The "gvs" estimator: frame checks, the choice of analysis per frame, and
// the tracking state's updates. The analyses are in gvs_still.cpp,
// gvs_pair.cpp, gvs_single.cpp and gvs_double.cpp (gvs_analysis.hpp); the
// tracking rules in gvs_tracking.cpp.
#include "gvs/dsp/gvs_estimator.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <string_view>

#include "gvs/dsp/frame_check.hpp"

namespace gvs::dsp {

GvsEstimator::GvsEstimator(const EstimatorConfig& config, const GvsEstimatorSettings& settings)
    : cam_(config.camera),
      set_(settings),
      size_(config.camera.width_px, config.camera.height_px),
      spectra_(size_),
      pair_(size_),
      track_(size_, pair_.left.size()) {
  if (size_.width < 64 || size_.height < 64) {
    throw std::invalid_argument("gvs estimator: camera.width_px/height_px must be at least 64 px");
  }
  if (!(cam_.mm_per_px > 0.0)) {
    throw std::invalid_argument("gvs estimator: camera.mm_per_px must be > 0");
  }
}

GvsEstimator::~GvsEstimator() = default;

void GvsEstimator::reset() { forget_tracking(track_); }

VelocityEstimate GvsEstimator::estimate(const FrameView& frame) {
  // The estimate refers to the middle of the light.
  const std::int64_t t_mid = mid_exposure_ns(frame.t_ns, frame.exposure);
  if (frame.gray.empty() || frame.gray.type() != CV_8UC1 || frame.gray.size() != size_) {
    reset();
    return no_estimate(frame.index, t_mid, Method::bad_frame);
  }
  const FrameStats stats = measure_frame(frame.gray);
  if (const std::optional<Method> problem = frame_problem(stats, set_.frame_check)) {
    VelocityEstimate e = no_estimate(frame.index, t_mid, *problem);
    note_unusable_frame(track_, e);
    return e;
  }

  FrameOutcome outcome;
  VelocityEstimate e;
  if (frame.exposure.pulse_count >= 2) {
    note_pair(track_.motion, false, {});
    const DoublePulseResult r = analyse_double_pulse(frame, t_mid, track_, cam_, set_, spectra_);
    e = r.estimate;
    outcome.sign_known = r.sign_known;
  } else {
    e = estimate_one_light(frame, t_mid, stats.mean_grey, outcome);
  }
  learn_sensor_pattern(frame, t_mid, stats.mean_grey, e, outcome.single_tried);
  e.tracking = speed_is_recent(track_.motion, t_mid, set_);
  update_tracking(track_, frame, t_mid, stats.mean_grey, e, outcome);
  return e;
}

VelocityEstimate GvsEstimator::estimate_one_light(const FrameView& frame, std::int64_t t_mid,
                                                  double mean_grey, FrameOutcome& outcome) {
  const PreviousFrame& prev = track_.previous;
  MotionMemory& motion = track_.motion;
  const double dt_s = static_cast<double>(t_mid - prev.t_mid_ns) * 1e-9;
  // A pair needs the same blur in both frames: with different exposures the
  // two streak kernels' sinc spectra differ in sign and fool the correlation.
  const double lit_us = frame.exposure.lit_time_us();
  const bool same_exposure = std::abs(lit_us - prev.lit_us) <= 0.2 * std::max(lit_us, prev.lit_us);
  const bool consecutive = prev.valid && !prev.double_pulse && same_exposure && dt_s > 0.0 && dt_s < 0.06;
  VelocityEstimate e;
  if (consecutive) {
    const StillCheck still = check_still(frame.gray, mean_grey, prev, set_);
    if (still.still) {
      e = no_estimate(frame.index, t_mid, Method::still);
      e.has_speed = true;
      e.has_yaw_rate = true;
      e.quality = std::clamp(1.0 - still.ratio / set_.still_ratio, 0.1, 1.0);
      note_pair(motion, false, {});
      return e;
    }
  }
  const auto pair = [&] {
    const PairResult r = analyse_pair(frame, t_mid, dt_s, mean_grey, track_, cam_, set_, pair_);
    outcome.halves = &pair_.current;
    note_pair(motion, r.matched, r.v_pair_mps);
    note_reversal(motion, r.reversal, r.v_pair_mps, frame.index);
    if (r.matched) outcome.sign_known = true;
    return r.estimate;
  };

  motion.mode = next_mode(motion, dt_s, cam_, set_);
  const bool tried_pair = motion.mode == MotionMemory::Mode::pair && consecutive;
  if (tried_pair) {
    const VelocityEstimate p = pair();
    if (p.quality > 0.0) return p;
  }
  // From here this frame is measured on its own: the next pair's slope
  // comes from this frame's estimate, not from an older pair.
  note_pair(motion, false, {});
  const StreakResult single = analyse_streak(frame, t_mid, mean_grey, track_, cam_, set_, spectra_);
  note_single(motion, single.note, t_mid);
  outcome.single_tried = true;
  outcome.sign_known = single.sign_known;
  e = single.estimate;
  // The pair failed: the frames no longer overlap, go single-frame.
  if (tried_pair && e.quality > 0.0) motion.mode = MotionMemory::Mode::single;
  // Single-frame without a speed and a streak that is not too long: too
  // slow for a streak length, so try the pair (and go back to pair mode if
  // it works). After an elongated spectrum the pair's velocity must account
  // for that streak.
  const bool elongated = motion.last_axis_anisotropy >= 0.8;
  // Not where a recent too-long streak says the car is faster than the
  // pair's longest shift: on 3 ms frames of 500 px streaks whose spectrum
  // reads less elongated than "too long" between two that do, the pair
  // matched nothing and cost about a third of the frame.
  if (!tried_pair && consecutive && !e.has_speed && !(elongated && single.note.too_long) &&
      pair_can_overlap(motion, t_mid, dt_s, cam_, set_)) {
    // A pair measures the mean velocity between the two frames, half a frame
    // old; without the previous frame's speed for the slope a turning,
    // braking car reads up to max_accel_mps2 * dt / 2 off (7 % and 1.6 deg
    // at 0.7 m/s on torcs_etrack2 crawl). The next pair has this one's slope.
    const bool slope_known =
        motion.last_valid && motion.last.has_speed && motion.last.index == frame.index - 1;
    const VelocityEstimate p = pair();
    const double streak_px = p.speed_mps * lit_us * 1e-6 / (cam_.mm_per_px * 1e-3);
    // A match must explain the streak, and follow the previous frame's
    // velocity: 250 px apart along a 384 px frame extent the circular
    // correlation peaks at the alias, 134 px the other way (`spin`
    // adaptive over-exposed at 5.4 km/h), and pair mode would then keep it.
    const bool credible = (!elongated || (p.has_speed && streak_px >= set_.pair_min_streak_px_elongated)) &&
                          follows_last_velocity(motion, p, frame.index, dt_s, set_);
    if (p.quality >= 0.5 && credible) {
      if (!elongated || slope_known) e = p;
      motion.mode = MotionMemory::Mode::pair;
    } else if (!credible) {
      note_pair(motion, false, {});  // a chance match: not a measurement
      outcome.sign_known = single.sign_known;
    }
  }
  return e;
}

void GvsEstimator::learn_sensor_pattern(const FrameView& frame, std::int64_t t_mid, double mean_grey,
                                        const VelocityEstimate& e, bool single_frame_tried) {
  // Fast motion (single-frame mode, or a streak longer than the frame): each
  // frame shows new ground, so column means hold only the fixed pattern.
  const bool fast = e.quality > 0.0 && e.has_direction &&
                    (e.method != Method::pair && e.method != Method::still);
  const bool slow = e.has_speed && e.speed_mps <= 2.0;
  if (fast && !slow) track_.pattern.learn_columns(frame.gray, mean_grey);
  // The pixel pattern from every frame whose ground moved on by a few
  // grains since the previous one (pairs included: each pixel then sees new
  // texture), and from frames without a speed where the pair did not match or
  // was not tried and the frame is not still: a dark frame at speed shows
  // little but the pattern, which is what is to be learnt. Not from a first
  // frame (nothing to compare it with), and not from an exposed
  // `short-streak` frame without a speed: sharp texture with nothing to show
  // it moved on (a standing car on ground too faint to be declared still
  // repeats it frame after frame, and the pattern learnt that ground: at
  // half ph_asphalt_04's contrast, 41 standing frames left it in the
  // pattern, and the moving frames after them, with the pattern taken out,
  // read a spectrum too round for a direction up to 40 km/h). An
  // under-exposed one (mean grey below unlearnt_max_mean_grey, as for the
  // dark pairs) still teaches it: there the sensor's offsets are most of the
  // frame, and the dark pairs of a crawl wait for the pattern learnt from
  // such frames. (Not the pixel SNR: fine sharp ground raises the noise
  // floor it is read from, and a standing car's frames would read dark.)
  if (track_.previous.valid) {
    const double dt_s = static_cast<double>(t_mid - track_.previous.t_mid_ns) * 1e-9;
    const double shift_px = e.speed_mps * dt_s / (cam_.mm_per_px * 1e-3);
    const bool moved = e.has_speed ? shift_px >= set_.pixel_pattern_min_shift_px
                                   : single_frame_tried && (e.method != Method::short_streak ||
                                                            mean_grey < set_.unlearnt_max_mean_grey);
    if (moved) track_.pattern.learn_pixels(frame.gray, mean_grey);
  }
}

/// Fills vx, vy, speed and direction from a vehicle-axes velocity.
void set_velocity(VelocityEstimate& e, Vec2 v, bool with_speed) {
  const double speed = std::hypot(v.x, v.y);
  // Below 0.01 m/s the direction is noise (truth.csv leaves it empty too).
  e.has_direction = speed >= VelocityEstimate::kStandstillMps;
  e.direction_deg = e.has_direction ? direction_deg(v) : 0.0;
  if (with_speed) {
    e.has_speed = true;
    e.vx_mps = v.x;
    e.vy_mps = v.y;
    e.speed_mps = speed;
  }
}

std::unique_ptr<VelocityEstimator> make_gvs_estimator(const EstimatorConfig& config) {
  return std::make_unique<GvsEstimator>(config);
}

}  // namespace gvs::dsp
