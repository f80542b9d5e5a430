// One-frame measurement of a blurred frame: the streak's axis and length.
// It gives the axis of motion only; choose_sign() picks forwards or backwards.
#include <algorithm>
#include <cmath>

#include "gvs/dsp/gvs_analysis.hpp"

namespace gvs::dsp {

namespace {

/// The spectrum of `gray` through `with` into `spectrum`, without the sensor's
/// pixel pattern (`pattern_out`) or else its column pattern (once learnt).
void take_spectrum(WindowedSpectrum& with, const cv::Mat& gray, cv::Mat& spectrum,
                   const SensorPattern& pattern, bool pattern_out) {
  if (pattern_out) {
    with.compute(gray, spectrum, pattern.pixels());
  } else {
    with.compute(gray, spectrum, pattern.columns());
  }
}

/// The streak axis of a frame, from the spectrum without the sensor pattern
/// that suits its light.
struct AxisSpectrum {
  StreakAxis axis;
  bool pattern_out = false;  ///< ws.spectrum is without the pixel pattern (a dark frame)
  bool nothing_learnt = false;  ///< dark, little texture and no pattern learnt yet: no axis
};

AxisSpectrum axis_spectrum(const cv::Mat& gray, double mean_grey, const TrackingState& track,
                           const GvsEstimatorSettings& set, SpectrumWorkspace& ws) {
  const SensorPattern& pattern = track.pattern;
  AxisSpectrum s;
  // A dark frame after a dark frame: straight to the spectrum without the
  // sensor's whole pattern (one DFT instead of two), unless it shows the
  // light is back.
  s.pattern_out = track.motion.last_single_dark && mean_grey < set.unlearnt_max_mean_grey &&
                  pattern.pixel_frames() >= set.pixel_pattern_min_frames;
  if (s.pattern_out) {
    take_spectrum(ws.tukey, gray, ws.spectrum, pattern, true);
    ws.blur.ring_gain(ws.spectrum, nullptr, 0.0, ws.ring_gain);
    s.axis = ws.blur.streak_axis(ws.spectrum, &ws.ring_gain);
    s.pattern_out = s.axis.texture_snr < set.pixel_pattern_exit_texture_snr;
  }
  if (!s.pattern_out) {
    take_spectrum(ws.tukey, gray, ws.spectrum, pattern, false);
    s.axis = ws.blur.streak_axis(ws.spectrum);
  }
  const bool dark = s.pattern_out || s.axis.texture_snr < set.pixel_pattern_max_texture_snr;
  // Nothing learnt yet, a dark frame and not much texture: the column
  // pattern, an endless streak along the columns, may be what rules the
  // spectrum (on the first under-exposed frame of `const`, SNR 6, an 8 px
  // streak read 6 deg off).
  s.nothing_learnt = s.axis.texture_snr < set.good_texture_snr && mean_grey < set.unlearnt_max_mean_grey &&
                     pattern.pixel_frames() < set.pixel_pattern_min_frames && pattern.columns() == nullptr;
  if (s.nothing_learnt) return s;
  if (dark && pattern.pixel_frames() >= set.pixel_pattern_min_frames && !s.pattern_out) {
    // Dark frame: without the sensor's whole pattern, and only the rings of
    // |k| where the texture shows (docs/estimator.md, "Dark frames").
    s.pattern_out = true;
    take_spectrum(ws.tukey, gray, ws.spectrum, pattern, true);
    ws.blur.ring_gain(ws.spectrum, nullptr, 0.0, ws.ring_gain);
    s.axis = ws.blur.streak_axis(ws.spectrum, &ws.ring_gain);
  }
  return s;
}

/// Mean grey over the RMS of the white noise per pixel: noise of variance
/// sigma^2 has the power sigma^2 sum(w^2) in every bin of the windowed
/// spectrum (Parseval), and the noise floor is measured beyond the texture.
double pixel_snr(double mean_grey, const SpectrumWorkspace& ws) {
  const double noise_power = ws.blur.noise_floor(ws.spectrum) / ws.tukey.window_energy();
  return noise_power > 0.0 ? mean_grey / std::sqrt(noise_power) : 0.0;
}

/// Where the streak end is looked for, and how clear it must be.
struct StreakSearch {
  double lo_px = 0.0;
  double hi_px = 0.0;
  double expected_px = 0.0;  ///< L predicted from the recent speed (0: none)
  double min_significance = 0.0;
  double min_length_px = 0.0;
  double max_background = 0.0;
  /// The longest streak the recent speed allows is beyond max_px: the end
  /// may lie outside the window.
  bool clipped = false;
};

/// Around L = v T / s from the last measured speed (recent by time, widened
/// for +-max_accel), because the texture's own grain can mimic a streak end;
/// everywhere, with a stricter significance and background, without a
/// recent speed. `max_px`: the longest measurable streak; `t_s`: light time.
StreakSearch streak_search(const MotionMemory& m, std::int64_t index, std::int64_t t_mid_ns, double max_px,
                           double t_s, double m_per_px, const GvsEstimatorSettings& set) {
  StreakSearch s;
  s.lo_px = set.min_streak_search_px;
  s.hi_px = max_px;
  s.min_significance = set.min_streak_significance;
  const std::int64_t age = index - m.speed_index;
  s.min_length_px = set.min_streak_px;
  s.max_background = set.max_streak_background_tracked;
  const double age_s = static_cast<double>(t_mid_ns - m.speed_t_ns) * 1e-9;
  // Recent by time, not by frame count: gvsd skips frames when processing
  // falls behind, and a skipped frame does not make the speed less known.
  if (m.has_speed && age >= 1 && age_s <= set.speed_memory_s) {
    const double slack_mps = set.max_accel_mps2 * age_s;
    const double v_lo = std::max(0.0, (1.0 - set.speed_window_fraction) * m.speed_mps - slack_mps);
    const double v_hi = (1.0 + set.speed_window_fraction) * m.speed_mps + slack_mps;
    s.lo_px = std::max(s.lo_px, v_lo * t_s / m_per_px - 2.0);
    s.clipped = v_hi * t_s / m_per_px + 2.0 > s.hi_px;
    s.hi_px = std::min(s.hi_px, v_hi * t_s / m_per_px + 2.0);
    s.expected_px = m.speed_mps * t_s / m_per_px;
  } else {
    s.min_significance = set.min_streak_significance_cold;
    s.min_length_px = set.min_streak_px_cold;
    s.max_background = set.max_streak_background;
    // ... and not shorter than a recent too-long streak allows (less what
    // max_accel_mps2 can take off since): seen in `sine` seed 4, a texture
    // "streak end" at 44 px (1.5 m/s) between 500 px streaks (16.7 m/s).
    const double floor_age_s = static_cast<double>(t_mid_ns - m.speed_floor_t_ns) * 1e-9;
    if (m.has_speed_floor && floor_age_s >= 0.0 && floor_age_s <= set.speed_memory_s) {
      const double v_floor = m.speed_floor_mps - set.max_accel_mps2 * floor_age_s;
      s.lo_px = std::max(s.lo_px, v_floor * t_s / m_per_px - 2.0);
    }
  }
  return s;
}

/// The streak end found along the axis, and what it may be used for.
struct StreakEnd {
  StreakLength length;
  bool clear = false;      ///< it stands out: its lag may give the axis
  bool has_speed = false;  ///< ... and its length the speed
  /// The deepest end, deep and significant, lies at the search's shortest
  /// length: the streak is that short or shorter.
  bool shorter_than_search = false;
  /// Ends as deep as this one that the cepstrum did not decide between: no
  /// speed, and not a streak too long to measure either.
  bool ambiguous = false;
};

/// The surface is circular: a streak end at lag L' also shows at lag
/// (frame - L') along an axis parallel to the rows or columns. A streak
/// longer than we measure (here 0.58-0.9 of the frame) thus fakes a
/// shorter one, and the flat Tukey window keeps that alias strong
/// (overlap 0.33 at 0.6 of the frame; Hann 0.07). accel seed 9: 226 px
/// streaks read as 159 px, three frames at quality 0.7, 30 % slow.
/// Without a recent speed to vouch for it, the length must also be found
/// through a Hann window. Only where an alias can land on the axis (within
/// 3 px of it across the frame) and be strong (from streaks up to 0.85 of
/// the frame: here L > 0.15 of it); one more forward DFT on such frames.
/// False: the length may be such an alias.
bool not_an_alias(const cv::Mat& gray, const StreakAxis& axis, const StreakLength& len,
                  const StreakSearch& search, const SensorPattern& pattern, bool pattern_out,
                  double axis_tan, SpectrumWorkspace& ws) {
  const bool along_rows = std::abs(axis.u_col) * gray.rows < 3.0;
  const bool along_cols = std::abs(axis.u_row) * gray.cols < 3.0;
  const double alias_min_px = 0.15 * (along_rows ? gray.rows : gray.cols);
  if (!(along_rows || along_cols) || len.length_px <= alias_min_px) return true;
  take_spectrum(ws.hann, gray, ws.hann_spectrum, pattern, pattern_out);
  const StreakLength check = ws.blur.streak_length(ws.hann_spectrum, axis, search.lo_px, search.hi_px, 0.0, axis_tan);
  // (Its sub-pixel fit divides by the Tukey window's overlap: a few
  // tenths of a pixel off at most, well inside the 3 % agreement.)
  return check.found && std::abs(check.length_px - len.length_px) <= std::max(2.0, 0.03 * len.length_px);
}

StreakEnd find_streak_end(const cv::Mat& gray, const StreakAxis& axis, bool axis_refined,
                          const StreakSearch& search, const SensorPattern& pattern, bool pattern_out,
                          bool well_lit, const GvsEstimatorSettings& set, SpectrumWorkspace& ws) {
  StreakEnd end;
  const StreakLength& len = end.length;
  // An axis not refined may be a few degrees off: the end is looked for
  // beside the ray too, and its lag then gives the axis (motion_axis).
  const double axis_tan = axis_refined ? 0.0 : std::tan(set.unrefined_axis_error_deg * kPi / 180.0);
  if (search.hi_px > search.lo_px + 2.0) {
    end.length =
        ws.blur.streak_length(ws.spectrum, axis, search.lo_px, search.hi_px, search.expected_px, axis_tan);
  }
  // The power cepstrum: a second reading of the same streak that weighs
  // every zero of the blur alike, looked at only where needed.
  int cepstrum_agrees = -1;  // not yet looked at
  double cepstrum_px = 0.0;
  const auto vouched = [&] {
    // The cepstrum sees the ground's own troughs too (a fixed lag of its
    // grain): it vouches only where the window holds every length the
    // recent speed allows, not for a trough found below a streak that may
    // have outgrown the window (torcs_wheel1 `accel` seed 3, frame 133:
    // 137 px from both readings for 170 px, beyond the 161 px measurable).
    if (search.clipped) return false;
    if (cepstrum_agrees < 0) {
      const StreakLength c = ws.blur.streak_length_cepstral(ws.spectrum, axis, search.lo_px, search.hi_px);
      cepstrum_px = c.found ? c.length_px : 0.0;
      cepstrum_agrees = c.found && std::abs(c.length_px - len.length_px) <=
                                       set.cepstrum_max_disagreement * len.length_px;
    }
    return cepstrum_agrees == 1;
  };
  // Rival ends as deep as the chosen one: the length the recent speed
  // predicts cannot choose, it lags an accelerating car (`const adaptive
  // under` seed 1 frame 309: a trough at 70 px chosen for 70 px predicted,
  // the streak's at 75 px, 6 % slow at quality 0.39). The cepstrum
  // decides: the end nearest to its length, and no speed unless they agree.
  end.ambiguous = len.found && len.rivals > 0 && !vouched();
  if (end.ambiguous && cepstrum_px > 0.0) {
    const StreakLength nearest =
        ws.blur.streak_length(ws.spectrum, axis, search.lo_px, search.hi_px, cepstrum_px, axis_tan);
    if (nearest.found &&
        std::abs(nearest.length_px - cepstrum_px) <= set.cepstrum_max_disagreement * nearest.length_px) {
      end.length = nearest;
      cepstrum_agrees = 1;
      end.ambiguous = false;
    }
  }
  // Without a recent speed, the length must also agree with how elongated the
  // spectrum is (anisotropy grows with L: ~0.85 at 40 px, ~0.97 at 150 px on
  // asphalt): a short "streak end" in a spectrum of endless streaks is texture.
  const bool cold = search.min_length_px >= set.min_streak_px_cold;
  const bool consistent = !cold || axis.anisotropy < 0.93 + 0.0003 * len.length_px;
  const bool accepted = len.found && len.depth >= set.min_streak_depth &&
                        len.significance >= search.min_significance && len.background <= search.max_background &&
                        len.length_px > search.lo_px + 0.5 && len.length_px < search.hi_px - 0.5;
  // A clear streak end: its lag gives the axis from axis_from_streak_end_px,
  // its length the speed from min_length.
  // A dark frame gives a speed only from a streak end up to
  // dark_max_streak_px: in 10-seed `const`/`accel` under-exposed runs, ends
  // of 107-162 px were found 5-25 % short (6 frames; measurements: commit
  // 944efc3).
  // A well-lit frame with a faint texture is blurred, not dark (a streak of
  // L px keeps about 1/L of the texture's power): its streak end counts down
  // to min_speed_texture_snr_lit when the cepstrum puts it at the same
  // length (cepstrum_max_disagreement); so does a well-lit frame's end
  // beyond dark_max_streak_px (docs/estimator.md, "Faint streaks on
  // well-lit ground").
  const bool faint = axis.texture_snr < set.min_speed_texture_snr;
  const bool lit_faint = well_lit && axis.texture_snr >= set.min_speed_texture_snr_lit;
  end.shorter_than_search = len.found && len.depth >= set.min_streak_depth &&
                            len.significance >= search.min_significance && len.length_px <= search.lo_px + 0.5;
  end.clear = consistent && accepted && (!faint || (lit_faint && vouched()));
  const bool beyond_dark_max = pattern_out && len.length_px > set.dark_max_streak_px;
  end.has_speed = end.clear && !end.ambiguous && len.length_px >= search.min_length_px &&
                  !(beyond_dark_max && !(well_lit && vouched()));
  // Two readings of one end, each off by its own texture: the speed takes
  // their mean (the lag keeps its direction).
  if (end.has_speed && cepstrum_agrees == 1) {
    const double scale = 0.5 * (1.0 + cepstrum_px / len.length_px);
    end.length.length_px *= scale;
    end.length.d_row_px *= scale;
    end.length.d_col_px *= scale;
  }
  if (end.has_speed && cold) {
    end.has_speed = not_an_alias(gray, axis, len, search, pattern, pattern_out, axis_tan, ws);
    // An alias's lag is not on the axis either: (frame - L', -d_across).
    end.clear = end.has_speed;
  }
  return end;
}

/// Longer streaks (refine_min_anisotropy): the axis refined on the spectral
/// line; on a dark frame weighted by the ring gain along the line itself,
/// where the texture stands out further.
StreakAxis refine_streak_axis(const StreakAxis& axis, bool pattern_out, bool line_sharp,
                              const GvsEstimatorSettings& set, SpectrumWorkspace& ws) {
  if (pattern_out) ws.blur.ring_gain(ws.spectrum, &axis, 2.0 * set.refine_sigma, ws.ring_gain);
  return ws.blur.refine_axis(ws.spectrum, axis, set.refine_sigma, 2, line_sharp,
                             pattern_out ? &ws.ring_gain : nullptr);
}

/// The unit axis of motion in vehicle axes (sign arbitrary). The streak
/// end's lag is the sharper estimate for streaks of some tens of pixels (the
/// spectrum's orientation also carries the texture's own anisotropy); from
/// ~100 px the refined line in the spectrum is sharper. On a dark frame the
/// refined line (`dark_line`: ring gain along it) is sharper at every length
/// it is refined at (from ~50 px): the end's lag is read through the noise
/// of the whole spectrum. Under-exposed 3 ms seed-1 runs, 5-15 km/h:
/// 0.14-0.20 deg RMS (docs/estimator.md, "Dark frames"; measurements:
/// commit fe69b64).
Vec2 motion_axis(const StreakAxis& axis, const StreakEnd& end, bool dark_line, bool line_sharp,
                 const CameraGeometry& cam, const GvsEstimatorSettings& set) {
  double u_row = axis.u_row;
  double u_col = axis.u_col;
  const StreakLength& len = end.length;
  if (end.clear && !dark_line && len.length_px >= set.axis_from_streak_end_px &&
      (len.length_px < set.axis_from_streak_end_max_px || !line_sharp)) {
    u_row = len.d_row_px / len.length_px;
    u_col = len.d_col_px / len.length_px;
  }
  return unit_vector(image_shift_to_velocity(u_row, u_col, 1.0, cam));
}

/// The velocity along the unit axis `a` times `sign`: with the speed
/// L = v T / s  =>  v = L s / T  (T: the time light reached the sensor, t_s)
/// when the streak end gave one, else the direction only.
void set_streak_velocity(VelocityEstimate& e, Vec2 a, double sign, const StreakEnd& end, double m_per_px,
                         double t_s) {
  const double speed = end.has_speed ? end.length.length_px * m_per_px / t_s : 0.0;
  if (end.has_speed) {
    set_velocity(e, {sign * a.x * speed, sign * a.y * speed}, true);
  } else {
    e.has_direction = true;  // the streak outgrew the frame: direction only
    e.direction_deg = direction_deg({sign * a.x, sign * a.y});
  }
}

/// Quality of a single-frame estimate without its sign's share: how
/// elongated the spectrum is (direction), how deep the streak edge is
/// (speed), and the texture power over the sensor noise.
double streak_quality(const StreakAxis& axis, const StreakEnd& end, bool pattern_out,
                      const GvsEstimatorSettings& set) {
  const double q_dir = std::clamp((axis.anisotropy - set.min_anisotropy) / 0.3, 0.05, 1.0);
  // Without a speed the direction is as good as the spectrum says when the
  // streak outgrew the search; but a streak shown shorter than the search
  // (a deep end at its shortest length) is not: with no speed known the
  // search starts at 16 px, and a streak that short carries the ground's
  // own grain in its axis (1.7-2.1 deg off at 14 px on torcs_wheel1,
  // docs/accuracy.md, "Photographed ground"); with a speed known, it is
  // shorter than that speed allows.
  double q_len = 1.0;
  if (end.has_speed) {
    q_len = std::clamp(end.length.depth / 0.25, 0.05, 1.0);
  } else if (end.shorter_than_search) {
    q_len = 0.05;
  }
  // Texture power over sensor noise: under-exposed long streaks leave little
  // texture, and the column pattern of the sensor then pulls the axis.
  // Measured: 5-14 deg RMS at SNR 1-3, 1-3 deg at 4-8, 0.1-0.4 deg from 10:
  // the quality falls with the square of the SNR below good_texture_snr.
  // Dark frames (measured with the pixel pattern taken out) are no better at
  // a higher SNR: 0.06-0.29 deg RMS in every SNR bin, max 1.3 deg (six
  // under-exposed seed-1 runs; docs/estimator.md, "Dark frames"): a fixed,
  // low quality.
  const double snr_ratio = std::min(axis.texture_snr / set.good_texture_snr, 1.0);
  const double q_snr = pattern_out ? set.dark_frame_quality : std::max(snr_ratio * snr_ratio, 0.001);
  return q_dir * q_len * q_snr;
}

}  // namespace

// BlurAnalyzer reads the columns 0 .. cols/2 only: the rest is not filled.
SpectrumWorkspace::SpectrumWorkspace(cv::Size frame_size)
    : tukey(frame_size, kWindowTaper, DftPlan::Direction::forward_real_to_half_complex),
      hann(frame_size, 1.0, DftPlan::Direction::forward_real_to_half_complex),
      blur(frame_size) {
  spectrum = cv::Mat::zeros(frame_size, CV_32FC2);
  hann_spectrum = cv::Mat::zeros(frame_size, CV_32FC2);
}

StreakResult analyse_streak(const FrameView& frame, std::int64_t t_mid_ns, double mean_grey,
                            const TrackingState& track, const CameraGeometry& cam,
                            const GvsEstimatorSettings& set, SpectrumWorkspace& ws) {
  static constexpr Method kNames[3] = {Method::blur_cont, Method::blur_energy, Method::blur_fwd};
  // Direction only, because the streak is longer than we can measure.
  static constexpr Method kLongNames[3] = {Method::streak_cont, Method::streak_energy, Method::streak_fwd};
  VelocityEstimate e = no_estimate(frame.index, t_mid_ns, Method::no_match);
  StreakResult result;
  const auto done = [&] {
    result.estimate = e;
    return result;
  };
  const AxisSpectrum spectrum = axis_spectrum(frame.gray, mean_grey, track, set, ws);
  if (spectrum.nothing_learnt) {
    e.method = Method::no_texture;
    return done();
  }
  StreakAxis axis = spectrum.axis;
  const bool pattern_out = spectrum.pattern_out;
  result.note = {.axis_measured = true, .anisotropy = axis.anisotropy, .dark = pattern_out};
  e.texture_snr = axis.texture_snr;
  e.pixel_snr = pixel_snr(mean_grey, ws);
  // Faint texture over the whole band: no direction, unless the streak is
  // long and the light good, when the line may hold it all (min_line_snr).
  const bool faint = axis.texture_snr < set.min_texture_snr;
  if (faint && !(e.well_lit() && pattern_out && axis.anisotropy >= set.refine_min_anisotropy)) {
    e.method = Method::no_texture;
    return done();
  }
  if (axis.anisotropy < set.min_anisotropy) {
    // Nearly isotropic: no blur, or a streak of a few pixels, whose axis is
    // the texture's own random anisotropy. No direction rather than a wrong one.
    e.method = Method::short_streak;
    return done();
  }
  const bool refine = axis.anisotropy >= set.refine_min_anisotropy;
  const bool line_sharp = refine && axis.texture_snr >= set.refine_high_k_min_texture_snr;
  if (refine) axis = refine_streak_axis(axis, pattern_out, line_sharp, set, ws);
  if (faint && ws.blur.line_snr(ws.spectrum, axis, 2.0 * set.refine_sigma) < set.min_line_snr) {
    e.method = Method::no_texture;
    return done();
  }

  // Longest streak we can measure: a fraction of the frame extent along the axis.
  const double extent = std::abs(axis.u_row) * frame.gray.rows + std::abs(axis.u_col) * frame.gray.cols;
  const double max_px = set.max_streak_fraction * extent;
  const double t_s = frame.exposure.lit_time_us() * 1e-6;
  const double m_per_px = cam.mm_per_px * 1e-3;
  const StreakSearch search = streak_search(track.motion, frame.index, t_mid_ns, max_px, t_s, m_per_px, set);
  const StreakEnd end =
      find_streak_end(frame.gray, axis, refine, search, track.pattern, pattern_out, e.well_lit(), set, ws);

  const Vec2 a = motion_axis(axis, end, pattern_out && refine, line_sharp, cam, set);
  const SignChoice sign = choose_sign(track.motion, a, t_mid_ns, 0.0, set);
  const auto source = static_cast<int>(sign.source);
  result.sign_known = sign.known;

  set_streak_velocity(e, a, sign.sign, end, m_per_px, t_s);
  // Quality: the spectrum, the streak end, and how the sign was decided.
  e.quality = streak_quality(axis, end, pattern_out, set) * sign_quality(sign.source);
  const bool too_long = !end.has_speed && !end.ambiguous && axis.anisotropy >= set.long_streak_anisotropy;
  if (too_long) {
    result.note.too_long = true;
    // Half the longest measurable streak: "too long" is also said of a
    // streak somewhat shorter whose end the gates refused.
    result.note.speed_floor_mps = 0.5 * max_px * m_per_px / t_s;
  }
  e.method = (too_long ? kLongNames : kNames)[source];
  return done();
}

}  // namespace gvs::dsp
