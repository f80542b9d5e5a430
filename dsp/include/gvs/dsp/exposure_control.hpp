// Exposure control: choose the next frame's exposure / LED strobe plan from
// the latest velocity estimate. A pure function (no state, no clock): the
// caller keeps the current plan and feeds back what it gets.
//
// Why: a ground point moves v/s pixels per second (s = metres per pixel).
// During a light time T it smears into a streak of L = v*T/s pixels. The
// estimator measures speed from L only while 10 px <= L <= 80 px or so
// (adaptive mode; below ~20 px the texture grain biases the length), or from the displacement d = v*dt_pulses/s between the two
// images of a double pulse (double_pulse mode). So T (or dt_pulses) must
// follow the speed: T = L_target * s / v.
#pragma once

#include "gvs/dsp/vocabulary.hpp"

namespace gvs::dsp {

enum class ExposureMode {
  fixed,        ///< keep the current plan unchanged
  adaptive,     ///< one strobe whose length keeps the streak ~40-80 px
  double_pulse  ///< two short pulses; their double image gives the displacement (PIV-like)
};

/// What the hardware and the optics allow, and what the estimator wants.
struct ExposureLimits {
  double mm_per_px = 0.1;              ///< ground sampling distance
  double frame_period_us = 16666.7;    ///< 1/fps: no exposure may be longer
  double max_exposure_us = 3000.0;     ///< longest continuous exposure (low speed, standstill)
  double min_pulse_us = 2.0;           ///< shortest LED pulse the driver can fire
  // adaptive (single strobe)
  double target_streak_px = 50.0;      ///< streak length aimed at when re-planning
  /// Re-plan when the predicted streak leaves [min_streak_px, max_streak_px].
  /// Short streaks read short, most with saturated pixels (`spin adaptive
  /// over`, seed 1: 20-30 px -2.5 % mean, 30-40 px -1.3 %, 40-50 px -0.9 %;
  /// normal light -0.7 / -0.6 / -0.4 %), and while the car brakes its streak
  /// shrinks until the re-plan, so short, biased lengths come in runs
  /// (docs/estimator.md, "Short streaks, faint streaks"; measurements:
  /// commit 525e81e).
  double min_streak_px = 40.0;
  double max_streak_px = 80.0;         ///<   [min_streak_px, max_streak_px] (hysteresis band)
  /// Streak aimed at on a frame that is not well lit (VelocityEstimate::
  /// well_lit): below the LED's rated pulse (~200 us) a longer strobe
  /// brings more light, and a longer streak a better-defined axis.
  double dark_target_streak_px = 70.0;
  /// Dark single-strobe frames: below this texture SNR (the estimator's own
  /// limit for a speed from a streak) a shorter strobe only loses light, so
  /// the controller takes max_exposure_us (direction from long streaks, as
  /// with a fixed exposure); up to twice it, a streak too long to measure
  /// does not shorten the strobe.
  double dark_streak_texture_snr = 4.0;
  // double pulse
  double target_shift_px = 100.0;      ///< displacement between the two images aimed at
  double min_shift_px = 50.0;          ///< re-plan when the predicted displacement leaves
  double max_shift_px = 150.0;         ///<   [min_shift_px, max_shift_px]
  double max_pulse_blur_px = 2.0;      ///< streak allowed within one pulse
  /// Dark frames: the pulses are lengthened (more light, and more streak per
  /// pulse, up to dark_max_pulse_blur_px) until the frame's texture SNR
  /// would reach this. Under-exposed above ~100 km/h two 2 px pulses leave
  /// an SNR of 0.5-1 (docs/estimator.md, "Dark frames").
  double min_pulse_texture_snr = 3.0;
  double dark_max_pulse_blur_px = 6.0;
  double second_pulse_energy = 1.0;    ///< energy (duration) of pulse 2 relative to pulse 1
  /// Below this speed double_pulse mode uses a continuous max_exposure_us
  /// exposure instead (consecutive frames overlap and pair correlation wins).
  double double_pulse_min_speed_mps = 1.5;
  /// Shorter side of the frame (px); 0 = not given. Below 384 px the
  /// displacement band (target, min, max shift) shrinks in proportion: the
  /// estimator finds a double image only up to ~0.45 of this side.
  double frame_short_side_px = 0.0;
  /// Estimates below this quality do not change the plan.
  double min_quality = 0.3;
};

/// The limits that follow from the camera: ground sampling (mm_per_px),
/// frame period (1/fps; fps <= 0 keeps the default) and the frame's shorter
/// side; everything else at its default.
ExposureLimits exposure_limits_for(const CameraGeometry& camera, double fps);

/// The plan for the next frame, from the estimate of the frame just measured
/// (`frame`: the light it was actually taken with) and the plan in force
/// (`current`: the last one returned; frames still in flight may predate it).
///  - fixed: returns `current`.
///  - adaptive: one LED strobe (pulse_count 1, the light overdriven) of
///    T = target_streak_px*s/v (dark_target_streak_px on a frame that is
///    not well lit), clamped to [min_pulse_us, max_exposure_us]
///    (continuous light at max_exposure_us); unchanged while the streak
///    predicted for `current` stays within [min_streak_px, max_streak_px].
///    Without a speed: a streak too long to measure (Method::streak_*)
///    gives T_frame/4 unless the estimator is still `tracking` a recent
///    speed (then one such frame is a miss: hold); a streak too short for
///    a direction (Method::short_streak) gives 4 T_frame; any other moving frame
///    below max_exposure_us, when the estimator is not `tracking` a recent
///    speed (a start-up miss), gives T_frame/2, and below min_pulse_us max_exposure_us again (a sweep over
///    the octaves that cannot lock up on a streak the estimator will not
///    measure without an earlier speed). Steps start from the frame's light
///    time, so frames in flight under an older plan repeat the plan made.
///    A dark frame with a direction (texture SNR below
///    dark_streak_texture_snr, and not VelocityEstimate::well_lit) gives
///    max_exposure_us; one below twice that never shortens the strobe. At
///    max_exposure_us a well-lit frame with a direction and no speed (a
///    streak the estimator cannot measure) starts the sweep down. A well-lit
///    frame without texture (Method::no_texture at the pixel SNR of a lit
///    frame: a streak long enough to average low-contrast ground away) steps
///    the sweep as a moving frame without a speed does, at any exposure.
///  - double_pulse: two pulses {0, p} and {dt, p*second_pulse_energy}, dt =
///    target_shift_px*s/v, p = b*s/v (>= min_pulse_us), b = max_pulse_blur_px
///    px of streak per pulse, or on a dark frame (texture SNR below
///    min_pulse_texture_snr) the streak that would bring the SNR there
///    (taking the SNR proportional to the light), up to
///    dark_max_pulse_blur_px; unchanged while the predicted displacement
///    stays within [min_shift_px, max_shift_px] (scaled to
///    frame_short_side_px) and the streak per pulse within [0.5 b, 1.5 b]; below
///    double_pulse_min_speed_mps a continuous max_exposure_us exposure.
///    Without a speed the separation shrinks 3x per frame, and restarts
///    from a 30 m/s guess when it cannot shrink further; at the continuous
///    exposure a well-lit frame without texture starts from that guess too.
/// A standstill returns to a continuous max_exposure_us exposure; a dark or
/// saturated frame keeps the plan, and so does a textureless one that is not
/// well lit (no light to judge the texture by) or comes while the estimator
/// still tracks a recent speed, and a speed of quality below min_quality.
ExposurePlan next_exposure(const VelocityEstimate& latest, const ExposurePlan& frame,
                           const ExposurePlan& current, ExposureMode mode, const ExposureLimits& limits);

/// The same, for a frame taken with `current` itself (no plan in flight).
ExposurePlan next_exposure(const VelocityEstimate& latest, const ExposurePlan& current,
                           ExposureMode mode, const ExposureLimits& limits);

/// Parses "fixed", "adaptive", "double-pulse" (also "double_pulse"). Returns
/// false for anything else (the caller names the allowed values).
bool parse_exposure_mode(const char* text, ExposureMode& mode);

}  // namespace gvs::dsp
