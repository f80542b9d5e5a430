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

#include "gvs/dsp/gvs_estimator.hpp"

namespace gvs::dsp {

namespace {

double pair_quality(const ImageShift& s, double min_peak_to_rms) {
  // Peak significance above the acceptance threshold, penalised when a
  // second peak competes.
  const double q = (s.peak_to_rms - min_peak_to_rms) / (2.0 * min_peak_to_rms);
  return std::clamp(q, 0.0, 1.0) * std::clamp(1.5 * (1.0 - s.second_ratio), 0.0, 1.0);
}

}  // namespace

void GvsEstimator::take_halves(const cv::Mat& gray, int slot, bool pattern_out) {
  if (pattern_out) {
    half_spectrum_.compute(gray(left_), spec_left_[slot], pixel_pattern_(left_));
    half_spectrum_.compute(gray(right_), spec_right_[slot], pixel_pattern_(right_));
  } else {
    half_spectrum_.compute(gray(left_), spec_left_[slot]);
    half_spectrum_.compute(gray(right_), spec_right_[slot]);
  }
}

VelocityEstimate GvsEstimator::estimate_pair(const FrameView& frame, std::int64_t t_mid_ns,
                                             double dt_s) {
  VelocityEstimate e = no_estimate(frame.index, t_mid_ns, Method::no_match);
  const int prev = 1 - cur_;
  // In the dark, both frames without the sensor's pixel pattern
  // (pair_pixel_pattern_min_frames; docs/estimator.md, "Dark frames",
  // tenth session).
  const bool pattern_out = cur_mean_grey_ < set_.unlearnt_max_mean_grey &&
                           pixel_frames_ >= set_.pair_pixel_pattern_min_frames;
  if (!prev_halves_valid_ || prev_halves_pattern_out_ != pattern_out) {
    take_halves(prev_gray_, prev, pattern_out);
  }
  take_halves(frame.gray, cur_, pattern_out);
  prev_halves_pattern_out_ = pattern_out;
  halves_this_frame_ = true;

  const ImageShift l = half_correlator_.correlate(spec_left_[prev], spec_left_[cur_],
                                                  set_.pair_exclude_px, set_.pair_max_shift_px);
  const ImageShift r = half_correlator_.correlate(spec_right_[prev], spec_right_[cur_],
                                                  set_.pair_exclude_px, set_.pair_max_shift_px);
  const bool good_l = l.found && l.peak_to_rms >= set_.pair_min_peak_to_rms;
  const bool good_r = r.found && r.peak_to_rms >= set_.pair_min_peak_to_rms;
  if (!good_l && !good_r) return e;

  // Both halves must see the same translation; rotation may only move rows
  // apart by omega dt (c_right - c_left) (up to 200 deg/s allowed here).
  const double baseline_px = static_cast<double>((right_.x + right_.width / 2) -
                                                 (left_.x + left_.width / 2));
  const double max_row_gap = deg_to_rad(200.0) * dt_s * baseline_px + 2.0;
  // Along the motion the peak is as wide as the streak (L = shift x light
  // time / dt): its sub-pixel fit scatters by about a tenth of L there
  // (`crawl` under, 19 px streaks: the halves at 98.0 and 100.0 px).
  const double streak_px =
      std::hypot(l.d_row_px, l.d_col_px) * frame.exposure.lit_time_us() * 1e-6 / dt_s;
  const double max_col_gap = 2.0 + 0.1 * streak_px;
  const bool agree = good_l && good_r && std::abs(l.d_col_px - r.d_col_px) < max_col_gap &&
                     std::abs(l.d_row_px - r.d_row_px) < max_row_gap;
  double d_row = 0.0;
  double d_col = 0.0;
  double quality = 0.0;
  if (agree) {
    d_row = 0.5 * (l.d_row_px + r.d_row_px);
    d_col = 0.5 * (l.d_col_px + r.d_col_px);
    quality = std::min(1.0, 0.5 * (pair_quality(l, set_.pair_min_peak_to_rms) +
                                   pair_quality(r, set_.pair_min_peak_to_rms)) + 0.2);
    e.has_yaw_rate = true;
    e.yaw_rate_dps = rad_to_deg((r.d_row_px - l.d_row_px) / (dt_s * baseline_px));
  } else {
    // Halves disagree (or one failed): trust the stronger one, at lower quality.
    const ImageShift& best = (good_l && (!good_r || l.peak_to_rms >= r.peak_to_rms)) ? l : r;
    d_row = best.d_row_px;
    d_col = best.d_col_px;
    quality = 0.5 * pair_quality(best, set_.pair_min_peak_to_rms);
  }
  if (quality < set_.pair_min_quality) return e;

  const Vec2 v_pair = image_shift_to_velocity(d_row, d_col, dt_s, cam_);
  // Plausibility: above 0.5 m/s the direction cannot turn by more than 60 deg
  // between frames (that would take > 30 m/s^2 of lateral acceleration).
  const double speed_pair = std::hypot(v_pair.x, v_pair.y);
  const double age_s = static_cast<double>(t_mid_ns - last_direction_t_ns_) * 1e-9;
  if (has_last_direction_ && last_sign_known_ && age_s < 0.1 && speed_pair > 0.5) {
    const double cos_turn = (v_pair.x * last_direction_.x + v_pair.y * last_direction_.y) / speed_pair;
    if (cos_turn < 0.5) return e;
  }
  Vec2 v = v_pair;
  // Half-frame lag compensation, clamped to a physical acceleration. The
  // slope comes from the previous pair (dt earlier), or else from the previous
  // single-frame estimate, which refers to the previous frame (dt/2 earlier),
  // whatever its quality: a dark frame's is low by design (at most 0.45)
  // while its speed is within ~1 % (`crawl` under, decelerating at 4 m/s^2:
  // the first pair after dark single frames was 2.8 deg and 5 % off without
  // it; a former gate at quality 0.3 kept such frames out, and no
  // normal-light run of docs/estimator.md changes without it).
  Vec2 dv{0.0, 0.0};
  if (last_pair_valid_) {
    dv = {0.5 * (v_pair.x - last_pair_v_.x), 0.5 * (v_pair.y - last_pair_v_.y)};
  } else if (last_valid_ && last_.has_speed && last_.index == frame.index - 1) {
    dv = {v_pair.x - last_.vx_mps, v_pair.y - last_.vy_mps};
  }
  const double max_dv = set_.max_accel_mps2 * dt_s / 2.0;
  v.x += std::clamp(dv.x, -max_dv, max_dv);
  v.y += std::clamp(dv.y, -max_dv, max_dv);
  last_pair_v_ = v_pair;
  last_pair_valid_ = true;

  e.method = Method::pair;
  sign_known_now_ = true;
  e.quality = quality;
  set_velocity(e, v, true);
  return e;
}

}  // namespace gvs::dsp
