// The rules that carry the "gvs" estimator's state from frame to frame
// (gvs_tracking.hpp).
#include "gvs/dsp/gvs_tracking.hpp"

#include <cmath>
#include <utility>

namespace gvs::dsp {

TrackingState::TrackingState(cv::Size frame_size, cv::Size half_size) : pattern(frame_size) {
  previous.gray.create(frame_size, CV_8UC1);
  previous.halves.left = cv::Mat::zeros(half_size, CV_32FC2);
  previous.halves.right = cv::Mat::zeros(half_size, CV_32FC2);
}

MotionMemory::Mode next_mode(const MotionMemory& m, double dt_s, const CameraGeometry& cam,
                             const GvsEstimatorSettings& set) {
  // Shift expected between this frame and the previous one, from the last estimate.
  if (!m.last_valid) return m.mode;  // unknown: keep the mode (pair first)
  if (!m.last.has_speed) return m.mode;  // no speed: keep the mode (a failing pair switches)
  const double shift_px = m.last.speed_mps * dt_s / (cam.mm_per_px * 1e-3);
  MotionMemory::Mode mode = m.mode;
  if (mode == MotionMemory::Mode::pair && shift_px > set.pair_leave_shift_px) mode = MotionMemory::Mode::single;
  if (mode == MotionMemory::Mode::single && shift_px < set.pair_enter_shift_px) mode = MotionMemory::Mode::pair;
  return mode;
}

SignChoice choose_sign(const MotionMemory& m, Vec2 axis, std::int64_t t_mid_ns, double energy_vote,
                       const GvsEstimatorSettings& set) {
  SignChoice c;
  const double age_s = static_cast<double>(t_mid_ns - m.direction_t_ns) * 1e-9;
  if (m.has_direction && age_s <= set.continuity_max_age_s) {
    const double dot = axis.x * m.direction.x + axis.y * m.direction.y;
    // Turning by more than ~70 deg between frames is not physical: then the
    // previous direction does not decide.
    if (std::abs(dot) > 0.35) {
      c.sign = dot >= 0.0 ? 1.0 : -1.0;
      c.source = SignSource::continuity;
      c.known = m.sign_known;  // continuity carries the last sign, measured or assumed
      return c;
    }
  }
  if (std::abs(energy_vote) >= set.min_energy_confidence) {
    c.sign = energy_vote > 0.0 ? 1.0 : -1.0;
    c.source = SignSource::energy;
    c.known = true;
    return c;
  }
  c.sign = axis.x >= 0.0 ? 1.0 : -1.0;  // a car mostly drives forwards
  c.source = SignSource::forward;
  c.known = false;
  return c;
}

double sign_quality(SignSource source) {
  constexpr double kQ[3] = {1.0, 0.7, 0.3};  // continuity, energy, forward prior
  return kQ[static_cast<int>(source)];
}

bool speed_is_recent(const MotionMemory& m, std::int64_t t_mid_ns, const GvsEstimatorSettings& set) {
  return m.has_speed && t_mid_ns > m.speed_t_ns &&
         static_cast<double>(t_mid_ns - m.speed_t_ns) * 1e-9 <= set.speed_memory_s;
}

double speed_floor_now_mps(const MotionMemory& m, std::int64_t t_mid_ns, const GvsEstimatorSettings& set) {
  const double age_s = static_cast<double>(t_mid_ns - m.speed_floor_t_ns) * 1e-9;
  if (!m.has_speed_floor || age_s < 0.0 || age_s > set.speed_memory_s) return 0.0;
  return std::max(0.0, m.speed_floor_mps - set.max_accel_mps2 * age_s);
}

bool pair_can_overlap(const MotionMemory& m, std::int64_t t_mid_ns, double dt_s, const CameraGeometry& cam,
                      const GvsEstimatorSettings& set) {
  const double pair_max_mps = set.pair_max_shift_px * cam.mm_per_px * 1e-3 / dt_s;
  return speed_floor_now_mps(m, t_mid_ns, set) <= pair_max_mps;
}

namespace {

/// |v - v0| <= speed_window_fraction |v0| + max_accel_mps2 dt: a velocity
/// the car can reach from v0 (speed speed0_mps) in dt.
bool within_reach(Vec2 v, Vec2 v0, double speed0_mps, double dt_s, const GvsEstimatorSettings& set) {
  return std::hypot(v.x - v0.x, v.y - v0.y) <= set.speed_window_fraction * speed0_mps + set.max_accel_mps2 * dt_s;
}

}  // namespace

bool follows_last_velocity(const MotionMemory& m, const VelocityEstimate& e, std::int64_t index, double dt_s,
                           const GvsEstimatorSettings& set) {
  const VelocityEstimate& last = m.last;
  if (!(m.last_valid && last.has_speed && last.has_direction && last.index == index - 1)) return true;
  if (!(e.has_speed && e.has_direction)) return true;
  return within_reach({e.vx_mps, e.vy_mps}, {last.vx_mps, last.vy_mps}, last.speed_mps, dt_s, set);
}

Reversal judge_reversal(const MotionMemory& m, Vec2 v, std::int64_t index, std::int64_t t_mid_ns, double dt_s,
                        const GvsEstimatorSettings& set) {
  const double age_s = static_cast<double>(t_mid_ns - m.direction_t_ns) * 1e-9;
  if (!(m.has_direction && m.sign_known && age_s <= set.continuity_max_age_s)) return Reversal::none;
  if (v.x * m.direction.x + v.y * m.direction.y >= 0.0) return Reversal::none;
  // The previous frame's speed (a standstill has no direction: v0 = 0).
  const VelocityEstimate& last = m.last;
  if (m.last_valid && last.has_speed && last.index == index - 1) {
    const Vec2 v0 = last.has_direction ? Vec2{last.vx_mps, last.vy_mps} : Vec2{0.0, 0.0};
    if (within_reach(v, v0, std::hypot(v0.x, v0.y), dt_s, set)) return Reversal::from_slow;
  }
  const Vec2 held = m.held_reversal_v_mps;
  if (m.has_held_reversal && m.held_reversal_index == index - 1 &&
      within_reach(v, held, std::hypot(held.x, held.y), dt_s, set)) {
    return Reversal::confirmed;
  }
  return Reversal::held;
}

void note_reversal(MotionMemory& m, Reversal r, Vec2 v_pair_mps, std::int64_t index) {
  m.has_held_reversal = r == Reversal::held;
  m.held_reversal_v_mps = v_pair_mps;
  m.held_reversal_index = index;
}

void note_pair(MotionMemory& m, bool matched, Vec2 v_pair_mps) {
  m.has_pair_v = matched;
  if (matched) m.pair_v_mps = v_pair_mps;
}

void note_single(MotionMemory& m, const SingleFrameNote& note, std::int64_t t_mid_ns) {
  m.last_single_dark = note.dark;
  if (note.axis_measured) m.last_axis_anisotropy = note.anisotropy;
  if (note.too_long) {
    m.has_speed_floor = true;
    m.speed_floor_mps = note.speed_floor_mps;
    m.speed_floor_t_ns = t_mid_ns;
  }
}

void update_tracking(TrackingState& t, const FrameView& frame, std::int64_t t_mid_ns, double mean_grey,
                     const VelocityEstimate& e, const FrameOutcome& outcome) {
  PreviousFrame& p = t.previous;
  frame.gray.copyTo(p.gray);
  p.valid = true;
  p.double_pulse = frame.exposure.pulse_count >= 2;
  p.lit_us = frame.exposure.lit_time_us();
  p.t_mid_ns = t_mid_ns;
  p.mean_grey = mean_grey;
  p.has_halves = outcome.halves != nullptr;
  if (outcome.halves != nullptr) std::swap(p.halves, *outcome.halves);

  MotionMemory& m = t.motion;
  m.last = e;
  m.last_valid = e.quality > 0.0;
  if (e.has_speed && e.quality > 0.0) {
    m.has_speed = true;
    m.speed_mps = e.speed_mps;
    m.speed_index = e.index;
    m.speed_t_ns = t_mid_ns;
  }
  if (e.has_direction && e.quality > 0.0) {
    const double a = deg_to_rad(e.direction_deg);
    m.direction = {std::cos(a), std::sin(a)};
    m.direction_t_ns = t_mid_ns;
    m.has_direction = true;
    m.sign_known = outcome.sign_known;
  }
}

void note_unusable_frame(TrackingState& t, const VelocityEstimate& e) {
  t.previous.valid = false;
  t.previous.has_halves = false;
  t.motion.has_pair_v = false;
  t.motion.last = e;
  t.motion.last_valid = false;
}

void forget_tracking(TrackingState& t) {
  t.previous.valid = false;
  t.previous.has_halves = false;
  MotionMemory& m = t.motion;
  m.last_valid = false;
  m.has_direction = false;
  m.has_speed = false;
  m.has_speed_floor = false;
  m.has_pair_v = false;
  m.has_held_reversal = false;
  m.mode = MotionMemory::Mode::pair;
  m.last_single_dark = false;
  t.pattern.forget();
}

}  // namespace gvs::dsp
