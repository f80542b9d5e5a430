// One-frame measurement of a blurred frame: the streak's axis and length.
// It gives the axis of motion only; choose_sign() picks forwards or backwards.
#include <algorithm>
#include <cmath>

#include "gvs/dsp/gvs_analysis.hpp"
#include "streak_end.hpp"

namespace gvs::dsp {

namespace {

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
double streak_quality(const StreakAxis& axis, const StreakEnd& end, bool pattern_out, bool lit_with_speed,
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
  // A well-lit frame whose streak end gave the speed: the SNR law is that
  // of a spectrum's axis without such an end (lit_speed_snr_quality).
  const double snr_ratio = std::min(axis.texture_snr / set.good_texture_snr, 1.0);
  double q_snr = pattern_out ? set.dark_frame_quality : std::max(snr_ratio * snr_ratio, 0.001);
  if (lit_with_speed) q_snr = std::max(q_snr, set.lit_speed_snr_quality);
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
  const StreakSearch search = streak_search(track.motion, frame.index, t_mid_ns, extent, t_s, m_per_px, set);
  const StreakEnd end =
      find_streak_end(frame.gray, axis, refine, search, track.pattern, pattern_out, e.well_lit(), set, ws);

  const Vec2 a = motion_axis(axis, end, pattern_out && refine, line_sharp, cam, set);
  const SignChoice sign = choose_sign(track.motion, a, t_mid_ns, 0.0, set);
  const auto source = static_cast<int>(sign.source);
  result.sign_known = sign.known;

  set_streak_velocity(e, a, sign.sign, end, m_per_px, t_s);
  // Quality: the spectrum, the streak end, and how the sign was decided.
  e.quality = streak_quality(axis, end, pattern_out, end.has_speed && e.well_lit(), set) * sign_quality(sign.source);
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
