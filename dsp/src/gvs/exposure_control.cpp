// Exposure control (see exposure_control.hpp for the physics).
#include "gvs/dsp/exposure_control.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>

namespace gvs::dsp {

namespace {

/// Image speed in pixels per microsecond for a ground speed in m/s.
double px_per_us(double speed_mps, const ExposureLimits& lim) {
  return speed_mps / (lim.mm_per_px * 1e-3) * 1e-6;
}

ExposurePlan continuous(double exposure_us) {
  ExposurePlan p;
  p.exposure_us = exposure_us;
  p.pulse_count = 0;
  return p;
}

/// One LED strobe of `lit_us` at the start of the exposure, or the continuous
/// longest exposure once it reaches that. A strobe is a pulse so that the
/// light can overdrive the LED (docs/hardware.md, "Light"): a 50 px streak
/// at 40 m/s lasts 125 us, which in continuous light has 1/24 the photons
/// of 3 ms.
ExposurePlan single_strobe(double lit_us, const ExposureLimits& lim) {
  if (lit_us >= lim.max_exposure_us * 0.99) return continuous(lim.max_exposure_us);
  ExposurePlan p;
  p.pulse_count = 1;
  p.pulses[0] = {0.0, lit_us};
  p.exposure_us = lit_us;
  return p;
}

/// Centre-to-centre time between the first two pulses (0 if not a double pulse).
double pulse_separation_us(const ExposurePlan& p) {
  if (p.pulse_count < 2) return 0.0;
  const double c0 = p.pulses[0].start_us + p.pulses[0].duration_us / 2.0;
  const double c1 = p.pulses[1].start_us + p.pulses[1].duration_us / 2.0;
  return c1 - c0;
}

ExposurePlan double_pulse_plan(double separation_us, double pulse_us, const ExposureLimits& lim) {
  const double p2 = std::max(lim.min_pulse_us, pulse_us * lim.second_pulse_energy);
  // Both pulses and their separation must fit in one frame period.
  const double max_sep = 0.9 * lim.frame_period_us - pulse_us - p2;
  const double sep = std::clamp(separation_us, 2.0 * std::max(pulse_us, p2), max_sep);
  ExposurePlan plan;
  plan.pulse_count = 2;
  plan.pulses[0] = {0.0, pulse_us};
  // Centres sep apart: start2 + p2/2 = sep + pulse/2.
  plan.pulses[1] = {sep + pulse_us / 2.0 - p2 / 2.0, p2};
  plan.exposure_us = plan.pulses[1].start_us + p2;
  return plan;
}

/// The estimator saw streaks too long to measure (direction only).
bool streak_too_long(const VelocityEstimate& e) {
  const bool long_streak =
      e.method == Method::streak_cont || e.method == Method::streak_energy || e.method == Method::streak_fwd;
  return e.has_direction && !e.has_speed && long_streak;
}

/// The estimator saw a streak too short to carry even a direction.
bool streak_too_short(const VelocityEstimate& e) { return e.method == Method::short_streak; }

/// The frame had texture and (probably) motion, but no speed came out of it:
/// a direction without speed, or no match at all (Method::no_match is the
/// estimator's outcome for texture without a measurable streak or pair shift;
/// dark, saturated and textureless frames have their own).
bool moving_without_speed(const VelocityEstimate& e) {
  return !e.has_speed && (e.has_direction || e.method == Method::no_match);
}

/// A well-lit frame in which the estimator found no texture: the light was
/// there, so the ground's texture was not, in the band the spectrum reads.
/// On low-contrast ground a streak much longer than the frame averages it
/// away (a photograph at half ph_asphalt_04's contrast: `no-texture` on every
/// adaptive frame at 2.4 ms from 80 km/h up, 540-930 px streaks), and a
/// shorter strobe brings it back; on ground without any texture no exposure
/// helps, and stepping costs nothing. (A frame with no contrast at all fails
/// frame_check before the spectrum and has no pixel SNR: not this.)
bool lit_without_texture(const VelocityEstimate& e) { return e.method == Method::no_texture && e.well_lit(); }

bool is_still(const VelocityEstimate& e) {
  return e.has_speed && e.speed_mps < VelocityEstimate::kStandstillMps;
}

/// Light time of a plan: the exposure for continuous light, else the pulses.
double lit_us(const ExposurePlan& p) { return p.pulse_count == 0 ? p.exposure_us : p.lit_time_us(); }

/// Displacement limits scaled to a small frame: the double image can only be
/// found up to ~0.45 of the shorter side (analyse_double_pulse), so the target
/// keeps 100 px at 384 px and shrinks in proportion below (e.g. 50 px at 192).
ExposureLimits fitted(const ExposureLimits& lim) {
  ExposureLimits l = lim;
  if (l.frame_short_side_px > 0.0) {
    const double scale = std::min(1.0, l.frame_short_side_px / 384.0);
    l.target_shift_px *= scale;
    l.min_shift_px *= scale;
    l.max_shift_px *= scale;
  }
  return l;
}

/// Where a sweep without a speed starts again, from the light time of the
/// frame that ended it: the longest exposure lowered by a third of an octave
/// more than the sweep before (3000, 2381, 1890, 3000, ... us), i.e.
/// max * 2^-k/3 with k = (round(3 log2(max / t_frame)) + 1) mod 3. Every
/// sweep halves, so restarting from the same exposure would try the same few
/// streak lengths forever; on ground where a cold start (no earlier speed to
/// search around) measures only a narrow band of lengths, a sweep whose
/// octaves all miss it then never finds a speed (docs/estimator.md,
/// "Exposure control"). Three phases put a tried length within 2^(1/6)
/// (12 %) of any length in every three sweeps.
ExposurePlan sweep_restart(double t_frame_us, const ExposureLimits& lim) {
  const double thirds = std::round(3.0 * std::log2(lim.max_exposure_us / std::max(t_frame_us, 1e-9)));
  const long phase = (static_cast<long>(thirds) % 3 + 3 + 1) % 3;
  return single_strobe(lim.max_exposure_us * std::exp2(-static_cast<double>(phase) / 3.0), lim);
}

ExposurePlan next_adaptive(const VelocityEstimate& latest, const ExposurePlan& frame,
                           const ExposurePlan& current, const ExposureLimits& lim) {
  const double t_cur = lit_us(current);
  // Steps without a speed start from the light time of the frame that was
  // measured, not from the plan: frames still in flight under an older plan
  // then ask for the plan already made, instead of stepping again.
  const double t_frame = lit_us(frame);
  if (is_still(latest)) return continuous(lim.max_exposure_us);
  // Dark: a streak length needs a texture SNR the short strobe does not
  // give (under-exposed, a 50 px streak at 40 m/s has 1/24 the light of
  // 3 ms). The longest exposure keeps the direction (0.1-0.2 deg RMS in the
  // dark, docs/estimator.md "Dark frames"); its streaks give a speed again
  // once the car is slow enough for them (up to 100 px).
  // (Only frames that gave a direction: texture, if dim, with its SNR
  // measured. A textureless frame has no SNR to judge the light by, so it
  // keeps the plan.)
  // A well-lit frame (pixel SNR, VelocityEstimate::well_lit) is not dark
  // whatever its texture SNR: faint streak ends there are the ground's own
  // low contrast, which a longer exposure does not raise.
  const bool measured_single = frame.pulse_count < 2 && latest.has_direction && latest.texture_snr > 0.0 &&
                               !latest.well_lit();
  if (measured_single && latest.texture_snr < lim.dark_streak_texture_snr) {
    return continuous(lim.max_exposure_us);
  }
  const bool dim = measured_single && latest.texture_snr < 2.0 * lim.dark_streak_texture_snr;
  if (streak_too_long(latest) && !latest.tracking && !dim) {
    // Direction without speed: the streak outgrew the frame. Shorten by an
    // octave, as the sweep below does, so no octave is skipped. (While a
    // speed from the last few frames says the streak is in the band, one
    // such frame is a miss, not a change: hold.)
    return single_strobe(std::clamp(t_frame / 2.0, lim.min_pulse_us, lim.max_exposure_us), lim);
  }
  if (streak_too_short(latest) && t_frame < lim.max_exposure_us * 0.99) {
    // No direction: a streak of a few pixels. With a recent speed (the car
    // slowed faster than the plan followed) lengthen hard: x4 puts a 15 px
    // streak at 60 px, inside the band. Without one, start the sweep again
    // near the top (sweep_restart): lengthening from where a sweep ended
    // would cycle over the same few octaves below the one the estimator can
    // measure.
    if (!latest.tracking) return sweep_restart(t_frame, lim);
    return single_strobe(std::clamp(t_frame * 4.0, lim.min_pulse_us, lim.max_exposure_us), lim);
  }
  // At the longest exposure a well-lit streak with a direction and no speed
  // is long, not short (a short one gives Method::short_streak): sweep down.
  // Not a doubtful one (below min_quality, as every estimate that changes
  // the plan): a run's first frame has no pair and no sign yet, and a slow
  // car's short streak there is measured by the next frame's pair at the
  // same exposure (pairs of unequal exposures do not match on every ground).
  // A well-lit frame without texture steps down too, at any exposure.
  const bool long_unmeasured =
      (latest.has_direction && latest.well_lit() && latest.quality >= lim.min_quality) || lit_without_texture(latest);
  if ((moving_without_speed(latest) || lit_without_texture(latest)) && !latest.tracking &&
      (t_frame < lim.max_exposure_us * 0.99 || long_unmeasured)) {
    // A shortened exposure that gives no speed: the streak may be still too
    // long, too short, or too faint for the estimator's stricter start-up
    // test (no earlier speed to search around). Step down an octave per frame
    // and start again near the longest exposure below the shortest pulse
    // (sweep_restart: a third of an octave lower each time): every octave is
    // visited, and one of them puts the streak in the measurable band. At
    // the longest exposure a frame without a direction (or a dim one) means
    // a slow car (the frame pairs measure it), so the plan is held there;
    // and a miss while the estimator still tracks a recent speed holds it
    // too.
    const double t_next = t_frame / 2.0;
    return t_next < lim.min_pulse_us ? sweep_restart(t_frame, lim) : single_strobe(t_next, lim);
  }
  if (latest.quality < lim.min_quality) return current;
  if (latest.has_speed) {
    const double v = px_per_us(latest.speed_mps, lim);
    const double streak_now = v * t_cur;  // L = v*T/s
    const bool single = current.pulse_count <= 1;
    const bool in_band = streak_now >= lim.min_streak_px && streak_now <= lim.max_streak_px;
    const bool pinned_long = streak_now < lim.min_streak_px && t_cur >= lim.max_exposure_us;
    const bool pinned_short = streak_now > lim.max_streak_px && t_cur <= lim.min_pulse_us;
    if (single && (in_band || pinned_long || pinned_short)) return current;
    const bool dark = latest.pixel_snr > 0.0 && !latest.well_lit();
    const double target_px = dark ? lim.dark_target_streak_px : lim.target_streak_px;
    const double t_new = target_px / std::max(v, 1e-12);
    return single_strobe(std::clamp(t_new, lim.min_pulse_us, lim.max_exposure_us), lim);
  }
  return current;
}

/// Streak per pulse (px) to aim at: max_pulse_blur_px, or on a dark
/// double-pulse frame the streak that brings its texture SNR to
/// min_pulse_texture_snr. With shot noise ruling, the SNR (power over noise
/// power) grows about as the light: SNR(b) = SNR_frame * b / b_frame
/// (docs/estimator.md, "Exposure control"). The answer does not depend on
/// the frame's own pulses, so it does not swing back once the longer pulses
/// have brought the light.
double pulse_blur_px(const VelocityEstimate& latest, const ExposurePlan& frame, double v_px_per_us,
                     const ExposureLimits& lim) {
  if (frame.pulse_count < 2 || !(latest.texture_snr > 0.0)) return lim.max_pulse_blur_px;
  const double blur_frame = v_px_per_us * frame.pulses[0].duration_us;
  const double wanted = blur_frame * lim.min_pulse_texture_snr / latest.texture_snr;
  return std::clamp(wanted, lim.max_pulse_blur_px, std::max(lim.max_pulse_blur_px, lim.dark_max_pulse_blur_px));
}

ExposurePlan next_double_pulse(const VelocityEstimate& latest, const ExposurePlan& frame,
                               const ExposurePlan& current, const ExposureLimits& lim) {
  if (is_still(latest)) return continuous(lim.max_exposure_us);
  if (latest.has_speed && latest.quality >= lim.min_quality) {
    if (latest.speed_mps < lim.double_pulse_min_speed_mps) {
      return continuous(lim.max_exposure_us);
    }
    const double v = px_per_us(latest.speed_mps, lim);
    const double blur_px = pulse_blur_px(latest, frame, v, lim);
    const double pulse_us = std::max(lim.min_pulse_us, blur_px / v);
    if (current.pulse_count >= 2) {
      const double shift_now = v * pulse_separation_us(current);  // d = v*dt/s
      const double blur_now = v * current.pulses[0].duration_us;
      const bool shift_ok = shift_now >= lim.min_shift_px && shift_now <= lim.max_shift_px;
      const bool blur_ok = blur_now <= 1.5 * blur_px &&
                           (blur_now >= 0.5 * blur_px ||
                            current.pulses[0].duration_us <= lim.min_pulse_us * 1.01);
      if (shift_ok && blur_ok) return current;
    }
    return double_pulse_plan(lim.target_shift_px / v, pulse_us, lim);
  }
  // At the continuous exposure a well-lit direction without a speed, with
  // no recent one, is a streak the estimator cannot measure: as too long.
  // Not a doubtful one (below min_quality, as every estimate that changes
  // the plan): a run's first frame, or the first after double-pulse frames,
  // has no pair and no sign yet, and a slow car's short streak there is
  // measured by the next frame's pair at the same exposure.
  // A well-lit frame without texture there is too (lit_without_texture).
  const bool long_unmeasured =
      frame.pulse_count < 2 && !latest.has_speed && !latest.tracking &&
      ((latest.has_direction && latest.well_lit() && latest.quality >= lim.min_quality) || lit_without_texture(latest));
  if (streak_too_long(latest) || long_unmeasured || (moving_without_speed(latest) && frame.pulse_count >= 2)) {
    // Direction without speed: streak or displacement too long.
    const double v_guess = px_per_us(30.0, lim);  // assume fast: 108 km/h
    const ExposurePlan restart = double_pulse_plan(
        lim.target_shift_px / v_guess, std::max(lim.min_pulse_us, lim.max_pulse_blur_px / v_guess), lim);
    if (frame.pulse_count >= 2) {
      // Shorter separation, from the measured frame's (in-flight frames
      // repeat the plan already made); when it cannot shrink any more, the
      // car may be too slow for any separation (1 km/h moves the ground
      // 1 px in 360 us): the continuous exposure, where consecutive frames
      // overlap and the pairs measure, and from there a clear streak
      // without a speed starts again from the fast guess.
      const double sep = pulse_separation_us(frame) / 3.0;
      if (sep < 2.0 * frame.pulses[0].duration_us) return continuous(lim.max_exposure_us);
      return double_pulse_plan(sep, frame.pulses[0].duration_us, lim);
    }
    return restart;
  }
  return current;
}

}  // namespace

ExposureLimits exposure_limits_for(const CameraGeometry& camera, double fps) {
  ExposureLimits l;
  l.mm_per_px = camera.mm_per_px;
  if (fps > 0.0) l.frame_period_us = 1e6 / fps;
  l.frame_short_side_px = std::min(camera.width_px, camera.height_px);
  return l;
}

ExposurePlan next_exposure(const VelocityEstimate& latest, const ExposurePlan& frame,
                           const ExposurePlan& current, ExposureMode mode, const ExposureLimits& limits) {
  switch (mode) {
    case ExposureMode::fixed:
      return current;
    case ExposureMode::adaptive:
      return next_adaptive(latest, frame, current, limits);
    case ExposureMode::double_pulse:
      return next_double_pulse(latest, frame, current, fitted(limits));
  }
  return current;
}

ExposurePlan next_exposure(const VelocityEstimate& latest, const ExposurePlan& current,
                           ExposureMode mode, const ExposureLimits& limits) {
  return next_exposure(latest, current, current, mode, limits);
}

bool parse_exposure_mode(const char* text, ExposureMode& mode) {
  if (text == nullptr) return false;
  if (std::strcmp(text, "fixed") == 0) {
    mode = ExposureMode::fixed;
  } else if (std::strcmp(text, "adaptive") == 0) {
    mode = ExposureMode::adaptive;
  } else if (std::strcmp(text, "double-pulse") == 0 || std::strcmp(text, "double_pulse") == 0) {
    mode = ExposureMode::double_pulse;
  } else {
    return false;
  }
  return true;
}

}  // namespace gvs::dsp
