// One-frame measurements: a blurred frame (streak axis and length) and a
// double-pulse frame (displacement between its two images). Both give the
// axis of motion only; resolve_sign() picks forwards or backwards.
#include <algorithm>
#include <cmath>

#include "gvs/dsp/gvs_estimator.hpp"

namespace gvs::dsp {

namespace {

Vec2 unit(Vec2 v) {
  const double n = std::hypot(v.x, v.y);
  return n > 0.0 ? Vec2{v.x / n, v.y / n} : Vec2{1.0, 0.0};
}

Method method_name(const Method names[3], int source) { return names[source]; }

double sign_quality(int source) {
  constexpr double kQ[3] = {1.0, 0.7, 0.3};  // continuity, energy, forward prior
  return kQ[source];
}

}  // namespace

VelocityEstimate GvsEstimator::estimate_single(const FrameView& frame, std::int64_t t_mid_ns) {
  static constexpr Method kNames[3] = {Method::blur_cont, Method::blur_energy, Method::blur_fwd};
  // Direction only, because the streak is longer than we can measure.
  static constexpr Method kLongNames[3] = {Method::streak_cont, Method::streak_energy, Method::streak_fwd};
  VelocityEstimate e = no_estimate(frame.index, t_mid_ns, Method::no_match);
  single_frame_tried_ = true;
  StreakAxis axis;
  // A dark frame after a dark frame: straight to the spectrum without the
  // sensor's whole pattern (one DFT instead of two), unless it shows the
  // light is back.
  pixel_pattern_in_use_ = last_single_dark_ && cur_mean_grey_ < set_.unlearnt_max_mean_grey &&
                          pixel_frames_ >= set_.pixel_pattern_min_frames;
  if (pixel_pattern_in_use_) {
    take_spectrum(full_spectrum_, frame.gray, spec_full_);
    blur_.ring_gain(spec_full_, nullptr, 0.0, ring_gain_);
    axis = blur_.streak_axis(spec_full_, &ring_gain_);
    pixel_pattern_in_use_ = axis.texture_snr < set_.pixel_pattern_exit_texture_snr;
  }
  last_single_dark_ = false;
  if (!pixel_pattern_in_use_) {
    take_spectrum(full_spectrum_, frame.gray, spec_full_);
    axis = blur_.streak_axis(spec_full_);
  }
  const bool dark = pixel_pattern_in_use_ || axis.texture_snr < set_.pixel_pattern_max_texture_snr;
  if (axis.texture_snr < set_.good_texture_snr && cur_mean_grey_ < set_.unlearnt_max_mean_grey &&
      pixel_frames_ < set_.pixel_pattern_min_frames && column_pattern() == nullptr) {
    // Nothing learnt yet, a dark frame and not much texture: the column
    // pattern, an endless streak along the columns, may be what rules the
    // spectrum (on the first under-exposed frame of `const`, SNR 6, an 8 px
    // streak read 6 deg off).
    e.method = Method::no_texture;
    return e;
  }
  if (dark && pixel_frames_ >= set_.pixel_pattern_min_frames && !pixel_pattern_in_use_) {
    // Dark frame: without the sensor's whole pattern, and only the rings of
    // |k| where the texture shows (docs/estimator.md, "Dark frames").
    pixel_pattern_in_use_ = true;
    take_spectrum(full_spectrum_, frame.gray, spec_full_);
    blur_.ring_gain(spec_full_, nullptr, 0.0, ring_gain_);
    axis = blur_.streak_axis(spec_full_, &ring_gain_);
  }
  last_single_dark_ = pixel_pattern_in_use_;
  last_axis_anisotropy_ = axis.anisotropy;
  e.texture_snr = axis.texture_snr;
  if (axis.texture_snr < set_.min_texture_snr) {
    e.method = Method::no_texture;
    return e;
  }
  if (axis.anisotropy < set_.min_anisotropy) {
    // Nearly isotropic: no blur, or a streak of a few pixels, whose axis is
    // the texture's own random anisotropy. No direction rather than a wrong one.
    e.method = Method::short_streak;
    return e;
  }
  const bool refine = axis.anisotropy >= set_.refine_min_anisotropy;
  const bool line_sharp = refine && axis.texture_snr >= set_.refine_high_k_min_texture_snr;
  if (refine && pixel_pattern_in_use_) {
    // The gain along the line itself: there the texture stands out further.
    blur_.ring_gain(spec_full_, &axis, 2.0 * set_.refine_sigma, ring_gain_);
  }
  if (refine) {
    axis = blur_.refine_axis(spec_full_, axis, set_.refine_sigma, 2, line_sharp,
                             pixel_pattern_in_use_ ? &ring_gain_ : nullptr);
  }

  // Longest streak we can measure: a fraction of the frame extent along the axis.
  const double extent = std::abs(axis.u_row) * size_.height + std::abs(axis.u_col) * size_.width;
  const double max_px = set_.max_streak_fraction * extent;
  const double t_s = frame.exposure.lit_time_us() * 1e-6;
  const double m_per_px = cam_.mm_per_px * 1e-3;
  // Where to look for the streak end: around L = v T / s from the last
  // measured speed (up to 10 frames old, widened for +-max_accel), because the
  // texture's own grain can mimic a streak end; everywhere, with a stricter
  // significance and background, without a recent speed.
  double lo = set_.min_streak_search_px;
  double hi = max_px;
  double min_significance = set_.min_streak_significance;
  const std::int64_t age = frame.index - last_speed_index_;
  double min_length = set_.min_streak_px;
  double max_background = set_.max_streak_background_tracked;
  double expected_px = 0.0;  // L predicted from the recent speed (0: none)
  const double age_s = static_cast<double>(t_mid_ns - last_speed_t_ns_) * 1e-9;
  // Recent by time, not by frame count: gvsd skips frames when processing
  // falls behind, and a skipped frame does not make the speed less known.
  if (has_last_speed_ && age >= 1 && age_s <= set_.speed_memory_s) {
    const double slack_mps = set_.max_accel_mps2 * age_s;
    const double v_lo = std::max(0.0, (1.0 - set_.speed_window_fraction) * last_speed_mps_ - slack_mps);
    const double v_hi = (1.0 + set_.speed_window_fraction) * last_speed_mps_ + slack_mps;
    lo = std::max(lo, v_lo * t_s / m_per_px - 2.0);
    hi = std::min(hi, v_hi * t_s / m_per_px + 2.0);
    expected_px = last_speed_mps_ * t_s / m_per_px;
  } else {
    min_significance = set_.min_streak_significance_cold;
    min_length = set_.min_streak_px_cold;
    max_background = set_.max_streak_background;
    // ... and not shorter than a recent too-long streak allows (less what
    // max_accel_mps2 can take off since): seen in `sine` seed 4, a texture
    // "streak end" at 44 px (1.5 m/s) between 500 px streaks (16.7 m/s).
    const double floor_age_s = static_cast<double>(t_mid_ns - speed_floor_t_ns_) * 1e-9;
    if (has_speed_floor_ && floor_age_s >= 0.0 && floor_age_s <= set_.speed_memory_s) {
      const double v_floor = speed_floor_mps_ - set_.max_accel_mps2 * floor_age_s;
      lo = std::max(lo, v_floor * t_s / m_per_px - 2.0);
    }
  }
  StreakLength len;
  if (hi > lo + 2.0) len = blur_.streak_length(spec_full_, axis, lo, hi, expected_px);
  // Without a recent speed, the length must also agree with how elongated the
  // spectrum is (anisotropy grows with L: ~0.85 at 40 px, ~0.97 at 150 px on
  // asphalt): a short "streak end" in a spectrum of endless streaks is texture.
  const bool cold = min_length >= set_.min_streak_px_cold;
  const bool consistent = !cold || axis.anisotropy < 0.93 + 0.0003 * len.length_px;
  const auto accepted = [&](const StreakLength& l) {
    return l.found && l.depth >= set_.min_streak_depth && l.significance >= min_significance &&
           l.background <= max_background && l.length_px > lo + 0.5 && l.length_px < hi - 0.5;
  };
  // A clear streak end: its lag gives the axis from axis_from_streak_end_px,
  // its length the speed from min_length.
  // A dark frame gives a speed only from a streak end up to
  // dark_max_streak_px: in 10-seed `const`/`accel` under-exposed runs, ends
  // of 107-162 px were found 5-25 % short (6 frames).
  bool clear_end = consistent && accepted(len) && axis.texture_snr >= set_.min_speed_texture_snr;
  bool has_speed = clear_end && len.length_px >= min_length &&
                   !(pixel_pattern_in_use_ && len.length_px > set_.dark_max_streak_px);
  if (has_speed && cold) {
    // The surface is circular: a streak end at lag L' also shows at lag
    // (frame - L') along an axis parallel to the rows or columns. A streak
    // longer than we measure (here 0.58-0.9 of the frame) thus fakes a
    // shorter one, and the flat Tukey window keeps that alias strong
    // (overlap 0.33 at 0.6 of the frame; Hann 0.07). accel seed 9: 226 px
    // streaks read as 159 px, three frames at quality 0.7, 30 % slow.
    // Without a recent speed to vouch for it, the length must also be found
    // through a Hann window. Only where an alias can land on the axis (within
    // 3 px of it across the frame) and be strong (from streaks up to 0.85 of
    // the frame: here L > 0.15 of it); one more forward DFT on such frames.
    const bool along_rows = std::abs(axis.u_col) * size_.height < 3.0;
    const bool along_cols = std::abs(axis.u_row) * size_.width < 3.0;
    const double alias_min_px = 0.15 * (along_rows ? size_.height : size_.width);
    if ((along_rows || along_cols) && len.length_px > alias_min_px) {
      take_spectrum(hann_spectrum_, frame.gray, spec_hann_);
      const StreakLength check = blur_.streak_length(spec_hann_, axis, lo, hi, 0.0);
      // (Its sub-pixel fit divides by the Tukey window's overlap: a few
      // tenths of a pixel off at most, well inside the 3 % agreement.)
      has_speed = check.found &&
                  std::abs(check.length_px - len.length_px) <= std::max(2.0, 0.03 * len.length_px);
      // An alias's lag is not on the axis either: (frame - L', -d_across).
      clear_end = has_speed;
    }
  }

  // Axis: the streak end's lag is the sharper estimate for streaks of some
  // tens of pixels (the spectrum's orientation also carries the texture's own
  // anisotropy); from ~100 px the refined line in the spectrum is sharper.
  // On a dark frame the refined line (ring gain along it) is sharper at every
  // length it is refined at (from ~50 px): the end's lag is read through the
  // noise of the whole spectrum. Under-exposed 3 ms seed-1 runs, 5-15 km/h:
  // 0.23-0.33 -> 0.14-0.20 deg RMS (docs/estimator.md, "Dark frames").
  double u_row = axis.u_row;
  double u_col = axis.u_col;
  const bool dark_line = pixel_pattern_in_use_ && refine;
  if (clear_end && !dark_line && len.length_px >= set_.axis_from_streak_end_px &&
      (len.length_px < set_.axis_from_streak_end_max_px || !line_sharp)) {
    u_row = len.d_row_px / len.length_px;
    u_col = len.d_col_px / len.length_px;
  }
  const Vec2 a = unit(image_shift_to_velocity(u_row, u_col, 1.0, cam_));
  double sign = 1.0;
  const auto source = static_cast<int>(resolve_sign(a, t_mid_ns, 0.0, sign));
  sign_known_now_ = source == 0 ? last_sign_known_ : source == 1;

  // L = v T / s  =>  v = L s / T  (T: the time light reached the sensor).
  const double speed = has_speed ? len.length_px * m_per_px / t_s : 0.0;
  if (has_speed) {
    set_velocity(e, {sign * a.x * speed, sign * a.y * speed}, true);
  } else {
    e.has_direction = true;  // the streak outgrew the frame: direction only
    e.direction_deg = direction_deg({sign * a.x, sign * a.y});
  }

  // Quality: how elongated the spectrum is (direction), how deep the streak
  // edge is (speed), and how the sign was decided.
  const double q_dir = std::clamp((axis.anisotropy - set_.min_anisotropy) / 0.3, 0.05, 1.0);
  const double q_len = has_speed ? std::clamp(len.depth / 0.25, 0.05, 1.0) : 1.0;
  // Texture power over sensor noise: under-exposed long streaks leave little
  // texture, and the column pattern of the sensor then pulls the axis.
  // Measured: 5-14 deg RMS at SNR 1-3, 1-3 deg at 4-8, 0.1-0.4 deg from 10:
  // the quality falls with the square of the SNR below good_texture_snr.
  // Dark frames (measured with the pixel pattern taken out) are no better at
  // a higher SNR: 0.1-0.3 deg RMS at every SNR, max ~1.3 deg (six
  // under-exposed seed-1 runs): a fixed, low quality.
  const double snr_ratio = std::min(axis.texture_snr / set_.good_texture_snr, 1.0);
  const double q_snr =
      pixel_pattern_in_use_ ? set_.dark_frame_quality : std::max(snr_ratio * snr_ratio, 0.001);
  e.quality = q_dir * q_len * q_snr * sign_quality(source);
  const bool too_long = !has_speed && axis.anisotropy >= set_.long_streak_anisotropy;
  if (too_long) {
    has_speed_floor_ = true;
    // Half the longest measurable streak: "too long" is also said of a
    // streak somewhat shorter whose end the gates refused.
    speed_floor_mps_ = 0.5 * max_px * m_per_px / t_s;
    speed_floor_t_ns_ = t_mid_ns;
  }
  e.method = method_name(too_long ? kLongNames : kNames, source);
  return e;
}

VelocityEstimate GvsEstimator::estimate_double(const FrameView& frame, std::int64_t t_mid_ns) {
  static constexpr Method kNames[3] = {Method::dpiv_cont, Method::dpiv_energy, Method::dpiv_fwd};
  VelocityEstimate e = no_estimate(frame.index, t_mid_ns, Method::no_match);
  last_pair_valid_ = false;
  // (No column pattern here: double_image() drops the spectrum rows it lives in.)
  full_spectrum_.compute(frame.gray, spec_full_);
  double texture_snr = blur_.streak_axis(spec_full_).texture_snr;
  if (texture_snr < set_.pixel_pattern_max_texture_snr && pixel_frames_ >= set_.pixel_pattern_min_frames) {
    // Dark frame (short pulses at speed): without the sensor's whole pattern.
    // `const double-pulse under`, 60-140 km/h: displacement found on 58 -> 85 %
    // of frames, 0.50 -> 0.18 deg RMS (98 % with the search window below;
    // docs/estimator.md, "Dark frames").
    full_spectrum_.compute(frame.gray, spec_full_, pixel_pattern_);
    texture_snr = blur_.streak_axis(spec_full_).texture_snr;
  }
  e.texture_snr = texture_snr;
  // Pulse centres c1, c2; the displacement d spans dt = c2 - c1.
  const LightPulse& p1 = frame.exposure.pulses[0];
  const LightPulse& p2 = frame.exposure.pulses[1];
  const double dt_s = ((p2.start_us + p2.duration_us / 2.0) - (p1.start_us + p1.duration_us / 2.0)) * 1e-6;
  if (!(dt_s > 0.0)) return e;
  double min_px = 4.0;
  double max_px = 0.45 * std::min(size_.width, size_.height);
  // With a recent speed, only displacements the car can reach since (as for
  // the streak length): a dark frame's noise once made a side peak 5.5x
  // too far at 140 km/h (`const double-pulse under`).
  const double age_s = static_cast<double>(t_mid_ns - last_speed_t_ns_) * 1e-9;
  if (has_last_speed_ && age_s > 0.0 && age_s <= set_.speed_memory_s) {
    const double slack_mps = set_.max_accel_mps2 * age_s;
    const double px_per_mps = dt_s / (cam_.mm_per_px * 1e-3);
    const double v_lo = std::max(0.0, (1.0 - set_.speed_window_fraction) * last_speed_mps_ - slack_mps);
    const double v_hi = (1.0 + set_.speed_window_fraction) * last_speed_mps_ + slack_mps;
    min_px = std::max(min_px, v_lo * px_per_mps - 2.0);
    max_px = std::min(max_px, v_hi * px_per_mps + 2.0);
    if (max_px <= min_px) return e;
  }
  DoubleImage pair = blur_.double_image(spec_full_, min_px, max_px);
  if (!pair.found || pair.height < set_.min_double_height ||
      pair.second_ratio > set_.max_double_second) {
    return e;
  }

  // Unequal energies: the third-order asymmetry says which way d points
  // (> 0: from the stronger image to the weaker one).
  double energy_vote = 0.0;
  const double energy_contrast = (p1.duration_us - p2.duration_us) / (p1.duration_us + p2.duration_us);
  if (std::abs(energy_contrast) > 0.1) {
    double_image_asymmetry(frame.gray, pair);
    if (std::abs(pair.skewness) > 0.1) energy_vote = energy_contrast > 0.0 ? pair.asymmetry : -pair.asymmetry;
  }
  const Vec2 v_axis = image_shift_to_velocity(pair.d_row_px, pair.d_col_px, dt_s, cam_);
  double sign = 1.0;
  const auto source = static_cast<int>(resolve_sign(unit(v_axis), t_mid_ns, energy_vote, sign));
  sign_known_now_ = source == 0 ? last_sign_known_ : source == 1;
  set_velocity(e, {sign * v_axis.x, sign * v_axis.y}, true);

  const double q_peak = std::clamp((pair.height - set_.min_double_height) / 0.15, 0.05, 1.0);
  const double q_unique = std::clamp(1.5 * (1.0 - pair.second_ratio), 0.05, 1.0);
  // Dark frames: within 0.2 deg and 0.4 % down to texture SNR ~2.5, but
  // below ~1 (under-exposed above ~100 km/h) one frame in ten is far off.
  const double q_snr = std::clamp(texture_snr / set_.good_double_texture_snr, 0.05, 1.0);
  e.quality = q_peak * q_unique * q_snr * sign_quality(source);
  e.method = method_name(kNames, source);
  return e;
}

}  // namespace gvs::dsp
