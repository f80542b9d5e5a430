// Frame-pair measurement (slow: consecutive frames overlap).
//
// Two overlapping half windows (left, right) are phase-correlated with the
// same windows of the previous frame. Their mean shift is the translation at
// the image centre; the difference of their row shifts is the rotation:
// a ground point at column offset c from the centre moves by
//   d_row = vx dt / s + omega dt c        (omega = yaw rate, CCW > 0)
// so omega = (d_row_right - d_row_left) / (dt (c_right - c_left)).
//
// The pair measures the mean velocity between the two frames' light centres,
// i.e. the velocity dt/2 before this frame. Under acceleration the previous
// pair (dt earlier) gives the slope: v(t) = v_pair + (v_pair - v_pair_prev)/2.
#include <algorithm>
#include <cmath>

#include "gvs/dsp/gvs_analysis.hpp"

namespace gvs::dsp {

namespace {

/// Left/right half windows, 5/8 of the width each (they overlap), full height.
cv::Rect half_window(cv::Size size, bool right) {
  const int w = (size.width * 5 / 8) & ~1;
  return {right ? size.width - w : 0, 0, w, size.height};
}

double pair_quality(const ImageShift& s, double min_peak_to_rms) {
  // Peak significance above the acceptance threshold, penalised when a
  // second peak competes.
  const double q = (s.peak_to_rms - min_peak_to_rms) / (2.0 * min_peak_to_rms);
  return std::clamp(q, 0.0, 1.0) * std::clamp(1.5 * (1.0 - s.second_ratio), 0.0, 1.0);
}

/// The half-window spectra of `gray` into `out`, without the sensor's pixel
/// pattern if `pattern_out`.
void take_halves(const cv::Mat& gray, bool pattern_out, const SensorPattern& pattern, PairWorkspace& ws,
                 HalfSpectra& out) {
  if (pattern_out) {
    ws.half_spectrum.compute(gray(ws.left), out.left, pattern.pixels()(ws.left));
    ws.half_spectrum.compute(gray(ws.right), out.right, pattern.pixels()(ws.right));
  } else {
    ws.half_spectrum.compute(gray(ws.left), out.left);
    ws.half_spectrum.compute(gray(ws.right), out.right);
  }
  out.pattern_out = pattern_out;
}

/// The yaw rate's standard error. A correlation peak's position scatters by
/// about pair_peak_scatter_px / (its peak-to-RMS) (the sub-pixel error of a
/// peak falls with its significance), and the yaw rate is the difference of
/// two such row shifts over dt and the baseline:
///   sigma_omega = sqrt(sigma_L^2 + sigma_R^2) / (dt (c_R - c_L)).
double yaw_rate_sigma_dps(const ImageShift& l, const ImageShift& r, double dt_s, double baseline_px,
                          const GvsEstimatorSettings& set) {
  const double scatter_l_px = set.pair_peak_scatter_px / l.peak_to_rms;
  const double scatter_r_px = set.pair_peak_scatter_px / r.peak_to_rms;
  return rad_to_deg(std::hypot(scatter_l_px, scatter_r_px) / (dt_s * baseline_px));
}

/// The image shift between the frames from the two halves' shifts.
struct HalvesShift {
  bool found = false;  ///< at least one half matched (then `quality` says how well)
  double d_row_px = 0.0;
  double d_col_px = 0.0;
  double quality = 0.0;
  bool has_yaw_rate = false;
  double yaw_rate_dps = 0.0;
};

HalvesShift combine_halves(const ImageShift& l, const ImageShift& r, double dt_s, double lit_us,
                           const PairWorkspace& ws, const GvsEstimatorSettings& set) {
  HalvesShift s;
  const bool good_l = l.found && l.peak_to_rms >= set.pair_min_peak_to_rms;
  const bool good_r = r.found && r.peak_to_rms >= set.pair_min_peak_to_rms;
  if (!good_l && !good_r) return s;
  s.found = true;

  // Both halves must see the same translation; rotation may only move rows
  // apart by omega dt (c_right - c_left) (up to 200 deg/s allowed here).
  const double baseline_px = static_cast<double>((ws.right.x + ws.right.width / 2) -
                                                 (ws.left.x + ws.left.width / 2));
  const double max_row_gap = deg_to_rad(200.0) * dt_s * baseline_px + 2.0;
  // Along the motion the peak is as wide as the streak (L = shift x light
  // time / dt): its sub-pixel fit scatters by about a tenth of L there
  // (`crawl` under, 19 px streaks: the halves at 98.0 and 100.0 px).
  const double streak_px = std::hypot(l.d_row_px, l.d_col_px) * lit_us * 1e-6 / dt_s;
  const double max_col_gap = 2.0 + 0.1 * streak_px;
  const bool agree = good_l && good_r && std::abs(l.d_col_px - r.d_col_px) < max_col_gap &&
                     std::abs(l.d_row_px - r.d_row_px) < max_row_gap;
  if (agree) {
    s.d_row_px = 0.5 * (l.d_row_px + r.d_row_px);
    s.d_col_px = 0.5 * (l.d_col_px + r.d_col_px);
    s.quality = std::min(1.0, 0.5 * (pair_quality(l, set.pair_min_peak_to_rms) +
                                     pair_quality(r, set.pair_min_peak_to_rms)) + 0.2);
    s.yaw_rate_dps = rad_to_deg((r.d_row_px - l.d_row_px) / (dt_s * baseline_px));
    s.has_yaw_rate = yaw_rate_sigma_dps(l, r, dt_s, baseline_px, set) <= set.pair_max_yaw_rate_sigma_dps;
  } else {
    // Halves disagree (or one failed): trust the stronger one, at lower quality.
    const ImageShift& best = (good_l && (!good_r || l.peak_to_rms >= r.peak_to_rms)) ? l : r;
    s.d_row_px = best.d_row_px;
    s.d_col_px = best.d_col_px;
    s.quality = 0.5 * pair_quality(best, set.pair_min_peak_to_rms);
  }
  return s;
}

/// Plausibility: above 0.5 m/s the direction cannot turn by more than 60 deg
/// between frames (that would take > 30 m/s^2 of lateral acceleration).
bool turn_is_plausible(Vec2 v_pair, const MotionMemory& m, std::int64_t t_mid_ns) {
  const double speed_pair = std::hypot(v_pair.x, v_pair.y);
  const double age_s = static_cast<double>(t_mid_ns - m.direction_t_ns) * 1e-9;
  if (m.has_direction && m.sign_known && age_s < 0.1 && speed_pair > 0.5) {
    const double cos_turn = (v_pair.x * m.direction.x + v_pair.y * m.direction.y) / speed_pair;
    if (cos_turn < 0.5) return false;
  }
  return true;
}

/// Half-frame lag compensation, clamped to a physical acceleration. The
/// slope comes from the previous pair (dt earlier), or else from the previous
/// single-frame estimate, which refers to the previous frame (dt/2 earlier),
/// whatever its quality: a dark frame's is low by design (at most 0.45)
/// while its speed is within ~1 %, and the first pair after dark single
/// frames of a decelerating car needs that slope (under-exposed 0-5 km/h;
/// measurements: commit 94b4da9). Failing both, from the last speed
/// measured within speed_memory_s, along the pair's direction: a car
/// braking at 4.6 m/s^2 through 2.2 km/h loses 11 % of its speed per frame:
/// there the first pair after two frames without a speed measures an
/// interval's mean 5.2 % above the speed at the frame, and this slope reads
/// it 3.3 % slow (procedural `crawl` under-exposed, seed 2, frame 400).
Vec2 compensate_lag(Vec2 v_pair, const MotionMemory& m, std::int64_t index, std::int64_t t_mid_ns, double dt_s,
                    const GvsEstimatorSettings& set) {
  Vec2 v = v_pair;
  Vec2 dv{0.0, 0.0};
  const double pair_speed = std::hypot(v_pair.x, v_pair.y);
  if (m.has_pair_v) {
    dv = {0.5 * (v_pair.x - m.pair_v_mps.x), 0.5 * (v_pair.y - m.pair_v_mps.y)};
  } else if (m.last_valid && m.last.has_speed && m.last.index == index - 1) {
    dv = {v_pair.x - m.last.vx_mps, v_pair.y - m.last.vy_mps};
  } else if (speed_is_recent(m, t_mid_ns, set) && m.speed_mps > VelocityEstimate::kStandstillMps &&
             pair_speed > 0.0) {
    // (Not from a standstill: when the car set off since is not known.)
    // The pair's mean velocity is that of dt/2 before this frame; only its
    // speed is carried forward: the direction extrapolated over this longer
    // span overshoots a turn (on that frame 1.45 deg off, the pair's own
    // direction 1.28).
    const double span_s = static_cast<double>(t_mid_ns - m.speed_t_ns) * 1e-9 - 0.5 * dt_s;
    if (span_s > 0.0) {
      const double dv_along = (pair_speed - m.speed_mps) * 0.5 * dt_s / span_s;
      dv = {dv_along * v_pair.x / pair_speed, dv_along * v_pair.y / pair_speed};
    }
  }
  const double max_dv = set.max_accel_mps2 * dt_s / 2.0;
  v.x += std::clamp(dv.x, -max_dv, max_dv);
  v.y += std::clamp(dv.y, -max_dv, max_dv);
  return v;
}

}  // namespace

PairWorkspace::PairWorkspace(cv::Size frame_size)
    : left(half_window(frame_size, false)),
      right(half_window(frame_size, true)),
      half_spectrum(left.size(), kWindowTaper, DftPlan::Direction::forward_real_to_half_complex),
      correlator(left.size()) {
  for (HalfSpectra* h : {&current, &previous}) {
    h->left = cv::Mat::zeros(left.size(), CV_32FC2);
    h->right = cv::Mat::zeros(right.size(), CV_32FC2);
  }
}

PairResult analyse_pair(const FrameView& frame, std::int64_t t_mid_ns, double dt_s, double mean_grey,
                        const TrackingState& track, const CameraGeometry& cam,
                        const GvsEstimatorSettings& set, PairWorkspace& ws) {
  PairResult result;
  VelocityEstimate e = no_estimate(frame.index, t_mid_ns, Method::no_match);
  // In the dark the sensor's pixel offsets, the same in both frames,
  // outweigh the streaked texture in most bins and vote for lag 0: both
  // frames without the pixel pattern once it is learnt
  // (pair_pixel_pattern_min_frames; docs/estimator.md, "Dark frames").
  const bool pattern_out = mean_grey < set.unlearnt_max_mean_grey &&
                           track.pattern.pixel_frames() >= set.pair_pixel_pattern_min_frames;
  const HalfSpectra* previous = &track.previous.halves;
  if (!track.previous.has_halves || track.previous.halves.pattern_out != pattern_out) {
    take_halves(track.previous.gray, pattern_out, track.pattern, ws, ws.previous);
    previous = &ws.previous;
  }
  take_halves(frame.gray, pattern_out, track.pattern, ws, ws.current);

  const ImageShift l = ws.correlator.correlate(previous->left, ws.current.left, set.pair_exclude_px,
                                               set.pair_max_shift_px);
  const ImageShift r = ws.correlator.correlate(previous->right, ws.current.right, set.pair_exclude_px,
                                               set.pair_max_shift_px);
  const HalvesShift s = combine_halves(l, r, dt_s, frame.exposure.lit_time_us(), ws, set);
  result.estimate = e;
  if (!s.found || s.quality < set.pair_min_quality) return result;

  const Vec2 v_pair = image_shift_to_velocity(s.d_row_px, s.d_col_px, dt_s, cam);
  if (!turn_is_plausible(v_pair, track.motion, t_mid_ns)) return result;
  result.reversal = judge_reversal(track.motion, v_pair, frame.index, t_mid_ns, dt_s, set);
  result.v_pair_mps = v_pair;
  if (result.reversal == Reversal::held) return result;
  const Vec2 v = compensate_lag(v_pair, track.motion, frame.index, t_mid_ns, dt_s, set);
  result.matched = true;

  e.method = Method::pair;
  e.has_yaw_rate = s.has_yaw_rate;
  e.yaw_rate_dps = s.yaw_rate_dps;
  e.quality = s.quality;
  set_velocity(e, v, true);
  result.estimate = e;
  return result;
}

}  // namespace gvs::dsp
