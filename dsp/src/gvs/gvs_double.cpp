// One-frame measurement of a frame lit by two pulses: the displacement
// between its two images. It gives the axis of motion only; choose_sign()
// picks forwards or backwards.
#include <algorithm>
#include <cmath>

#include "gvs/dsp/gvs_analysis.hpp"

namespace gvs::dsp {

namespace {

/// A double-pulse frame's spectrum (in ws.spectrum) and its texture SNR.
struct DoublePulseSpectrum {
  double texture_snr = 0.0;
  bool dark = false;  ///< without the sensor's whole pattern, and ws.ring_gain filled
};

/// The spectrum of a double-pulse frame; a dark frame's without the sensor's
/// whole pattern, with the Wiener gain of its rings (double_pulse.cpp).
DoublePulseSpectrum double_pulse_spectrum(const cv::Mat& gray, const SensorPattern& pattern,
                                          const GvsEstimatorSettings& set, SpectrumWorkspace& ws) {
  DoublePulseSpectrum s;
  // (No column pattern here: double_image() drops the spectrum rows it lives in.)
  ws.tukey.compute(gray, ws.spectrum);
  s.texture_snr = ws.blur.streak_axis(ws.spectrum).texture_snr;
  s.dark = s.texture_snr < set.pixel_pattern_max_texture_snr && pattern.pixel_frames() >= set.pixel_pattern_min_frames;
  if (s.dark) {
    // Dark frame (short pulses at speed): without the sensor's whole pattern,
    // whose pixel offsets (10x the temporal noise in the dark) would bury the
    // texture's double image (docs/estimator.md, "Dark frames"; with the
    // search window below, `const double-pulse under` reads 60-140 km/h on
    // 100 % of frames at 0.059 deg RMS, in that run's section).
    ws.tukey.compute(gray, ws.spectrum, pattern.pixels());
    s.texture_snr = ws.blur.streak_axis(ws.spectrum).texture_snr;
    ws.blur.ring_gain(ws.spectrum, nullptr, 0.0, ws.ring_gain);
  }
  return s;
}

/// The displacements searched, min_px <= |d| <= max_px (none: max_px <= min_px).
struct DisplacementSearch {
  double min_px = 4.0;
  double max_px = 0.0;
};

/// With a recent speed, only displacements the car can reach since (as for
/// the streak length): a dark frame's noise once made a side peak 5.5x
/// too far at 140 km/h (`const double-pulse under`). `dt_s`: between the pulses.
DisplacementSearch displacement_search(const MotionMemory& m, cv::Size frame, std::int64_t t_mid_ns, double dt_s,
                                       const CameraGeometry& cam, const GvsEstimatorSettings& set) {
  DisplacementSearch s;
  s.max_px = 0.45 * std::min(frame.width, frame.height);
  const double age_s = static_cast<double>(t_mid_ns - m.speed_t_ns) * 1e-9;
  if (m.has_speed && age_s > 0.0 && age_s <= set.speed_memory_s) {
    const double slack_mps = set.max_accel_mps2 * age_s;
    const double px_per_mps = dt_s / (cam.mm_per_px * 1e-3);
    const double v_lo = std::max(0.0, (1.0 - set.speed_window_fraction) * m.speed_mps - slack_mps);
    const double v_hi = (1.0 + set.speed_window_fraction) * m.speed_mps + slack_mps;
    s.min_px = std::max(s.min_px, v_lo * px_per_mps - 2.0);
    s.max_px = std::min(s.max_px, v_hi * px_per_mps + 2.0);
  }
  return s;
}

/// Unequal energies: the third-order asymmetry says which way d points
/// (> 0: from the stronger image to the weaker one). 0: no vote.
double energy_vote(const FrameView& frame, DoubleImage& pair) {
  const LightPulse& p1 = frame.exposure.pulses[0];
  const LightPulse& p2 = frame.exposure.pulses[1];
  double vote = 0.0;
  const double energy_contrast = (p1.duration_us - p2.duration_us) / (p1.duration_us + p2.duration_us);
  if (std::abs(energy_contrast) > 0.1) {
    double_image_asymmetry(frame.gray, pair);
    if (std::abs(pair.skewness) > 0.1) vote = energy_contrast > 0.0 ? pair.asymmetry : -pair.asymmetry;
  }
  return vote;
}

}  // namespace

DoublePulseResult analyse_double_pulse(const FrameView& frame, std::int64_t t_mid_ns,
                                       const TrackingState& track, const CameraGeometry& cam,
                                       const GvsEstimatorSettings& set, SpectrumWorkspace& ws) {
  static constexpr Method kNames[3] = {Method::dpiv_cont, Method::dpiv_energy, Method::dpiv_fwd};
  VelocityEstimate e = no_estimate(frame.index, t_mid_ns, Method::no_match);
  DoublePulseResult result;
  const auto done = [&] {
    result.estimate = e;
    return result;
  };
  const DoublePulseSpectrum spectrum = double_pulse_spectrum(frame.gray, track.pattern, set, ws);
  const double texture_snr = spectrum.texture_snr;
  e.texture_snr = texture_snr;
  // Pulse centres c1, c2; the displacement d spans dt = c2 - c1.
  const LightPulse& p1 = frame.exposure.pulses[0];
  const LightPulse& p2 = frame.exposure.pulses[1];
  const double dt_s = ((p2.start_us + p2.duration_us / 2.0) - (p1.start_us + p1.duration_us / 2.0)) * 1e-6;
  if (!(dt_s > 0.0)) return done();
  const DisplacementSearch search = displacement_search(track.motion, frame.gray.size(), t_mid_ns, dt_s, cam, set);
  if (search.max_px <= search.min_px) return done();
  DoubleImage pair =
      ws.blur.double_image(ws.spectrum, search.min_px, search.max_px, spectrum.dark ? &ws.ring_gain : nullptr);
  if (!pair.found || pair.height < set.min_double_height ||
      pair.second_ratio > set.max_double_second) {
    return done();
  }

  const double vote = energy_vote(frame, pair);
  const Vec2 v_axis = image_shift_to_velocity(pair.d_row_px, pair.d_col_px, dt_s, cam);
  const SignChoice sign = choose_sign(track.motion, unit_vector(v_axis), t_mid_ns, vote, set);
  const auto source = static_cast<int>(sign.source);
  result.sign_known = sign.known;
  set_velocity(e, {sign.sign * v_axis.x, sign.sign * v_axis.y}, true);

  const double q_peak = std::clamp((pair.height - set.min_double_height) / 0.15, 0.05, 1.0);
  const double q_unique = std::clamp(1.5 * (1.0 - pair.second_ratio), 0.05, 1.0);
  // Dark frames: within 0.2 deg and 0.4 % down to texture SNR ~2.5, but
  // below ~1 (under-exposed above ~100 km/h) one frame in ten is far off.
  const double q_snr = std::clamp(texture_snr / set.good_double_texture_snr, 0.05, 1.0);
  e.quality = q_peak * q_unique * q_snr * sign_quality(sign.source);
  e.method = kNames[source];
  return done();
}

}  // namespace gvs::dsp
