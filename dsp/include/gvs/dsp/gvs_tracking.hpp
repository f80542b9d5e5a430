// What the "gvs" estimator carries from one frame to the next, as one value
// (TrackingState), and the rules that read and update it. The analyses
// (gvs_analysis.hpp) only read it; GvsEstimator::estimate() updates it: the
// note_* rules right after an analysis, the sensor pattern from the frame,
// and update_tracking() once the frame's estimate is known.
#pragma once

#include <cstdint>

#include <opencv2/core/mat.hpp>

#include "gvs/dsp/vocabulary.hpp"
#include "gvs/dsp/gvs_settings.hpp"
#include "gvs/dsp/sensor_pattern.hpp"

namespace gvs::dsp {

/// The pair's spectra of one frame's two half windows (gvs_pair.cpp):
/// columns 0 .. cols/2 only (the phase correlation reads no more; the rest
/// stays zero).
struct HalfSpectra {
  cv::Mat left;   ///< CV_32FC2
  cv::Mat right;  ///< CV_32FC2
  bool pattern_out = false;  ///< taken without the sensor's pixel pattern
};

/// The previous frame, as far as the next one needs it.
struct PreviousFrame {
  bool valid = false;
  cv::Mat gray;  ///< its pixels (CV_8UC1; a buffer made once)
  bool double_pulse = false;
  double lit_us = 0.0;
  std::int64_t t_mid_ns = 0;  ///< the middle of its light
  double mean_grey = 0.0;
  bool has_halves = false;  ///< `halves` hold its half spectra (it was analysed as a pair)
  HalfSpectra halves;
};

/// The motion as the estimates so far describe it.
struct MotionMemory {
  /// pair: consecutive frames overlap (slow); single: one frame at a time.
  enum class Mode { pair, single };
  Mode mode = Mode::pair;

  VelocityEstimate last;    ///< the previous output
  bool last_valid = false;  ///< ... and it measured something (quality > 0)

  /// The last measured speed: where the streak end and the double image are looked for.
  bool has_speed = false;
  double speed_mps = 0.0;
  std::int64_t speed_index = 0;
  std::int64_t speed_t_ns = 0;

  /// The last measured direction (unit vector, vehicle axes): decides the sign.
  bool has_direction = false;
  Vec2 direction{1.0, 0.0};
  std::int64_t direction_t_ns = 0;
  /// That direction's sign was measured (pair, pulse energies, or continuity
  /// from a measured one), not assumed (forward prior).
  bool sign_known = false;

  /// A streak too long to measure says the speed is at least half the
  /// longest measurable streak's (floor for a streak length found without a
  /// recent speed: a 500 px streak cannot become a 44 px one in one frame).
  bool has_speed_floor = false;
  double speed_floor_mps = 0.0;
  std::int64_t speed_floor_t_ns = 0;

  /// The previous frame's raw pair velocity (the next pair's lag compensation).
  bool has_pair_v = false;
  Vec2 pair_v_mps{};

  /// The last single-frame analysis took the sensor's pixel pattern out (a dark frame).
  bool last_single_dark = false;
  /// Spectrum anisotropy of the last single-frame analysis that measured an
  /// axis (forget_tracking() keeps it).
  double last_axis_anisotropy = 1.0;

  /// A pair that reversed the measured direction with no slow frame before
  /// it (judge_reversal): held back until the next frame's pair agrees.
  bool has_held_reversal = false;
  Vec2 held_reversal_v_mps{};
  std::int64_t held_reversal_index = 0;
};

/// Everything the estimator carries between frames.
struct TrackingState {
  /// Buffers for frames of `frame_size` and the pair's half windows of `half_size`.
  TrackingState(cv::Size frame_size, cv::Size half_size);

  PreviousFrame previous;
  MotionMemory motion;
  SensorPattern pattern;  ///< the sensor's fixed pattern, learnt from frames of moving ground
};

/// Pair or single-frame mode for a frame dt_s after the last estimate, from
/// the shift its speed predicts, with hysteresis (pair_leave_shift_px,
/// pair_enter_shift_px). Without a last speed the mode stays.
MotionMemory::Mode next_mode(const MotionMemory& m, double dt_s, const CameraGeometry& cam,
                             const GvsEstimatorSettings& set);

/// What decided the sign of a direction (the method's suffix).
enum class SignSource { continuity, energy, forward };

struct SignChoice {
  double sign = 1.0;  ///< +1 or -1
  SignSource source = SignSource::forward;
  bool known = false;  ///< measured (energy, or continuity from a known sign), not assumed
};

/// How far an estimate is trusted for the way its sign was decided (a
/// factor of its quality): continuity 1, pulse energies 0.7, forward prior 0.3.
double sign_quality(SignSource source);

/// The sign of a unit axis in vehicle axes: continuity with the last
/// direction (younger than continuity_max_age_s, turn < ~70 deg), else the
/// pulse-energy vote (|vote| >= min_energy_confidence), else forwards.
SignChoice choose_sign(const MotionMemory& m, Vec2 axis_vehicle, std::int64_t t_mid_ns,
                       double energy_vote, const GvsEstimatorSettings& set);

/// A speed was measured within speed_memory_s before t_mid_ns (VelocityEstimate::tracking).
bool speed_is_recent(const MotionMemory& m, std::int64_t t_mid_ns, const GvsEstimatorSettings& set);

/// The least speed the car can have at t_mid_ns from a recent too-long
/// streak (its speed floor, within speed_memory_s), less what
/// max_accel_mps2 can take off since: v >= v_floor - a_max * age. 0 without one.
double speed_floor_now_mps(const MotionMemory& m, std::int64_t t_mid_ns, const GvsEstimatorSettings& set);

/// Two frames dt_s apart can overlap for the pair: the speed floor now
/// (speed_floor_now_mps) is within the pair's longest shift,
/// pair_max_shift_px in dt_s. False: the pair cannot match, do not try it.
bool pair_can_overlap(const MotionMemory& m, std::int64_t t_mid_ns, double dt_s, const CameraGeometry& cam,
                      const GvsEstimatorSettings& set);

/// `e`, of frame `index` dt_s after the previous one, is a velocity the car
/// can have reached from the previous frame's (within speed_window_fraction
/// of its speed plus max_accel_mps2 dt_s, as vectors); true when the
/// previous frame gave none to compare with.
bool follows_last_velocity(const MotionMemory& m, const VelocityEstimate& e, std::int64_t index, double dt_s,
                           const GvsEstimatorSettings& set);

/// After a pair attempt: its raw velocity is the next pair's slope if it matched.
void note_pair(MotionMemory& m, bool matched, Vec2 v_pair_mps);

/// What judge_reversal says of a pair velocity.
enum class Reversal {
  none,       ///< not against a measured direction (or no recent one)
  from_slow,  ///< against it, but the previous frame measured a speed the car can reverse from in dt
  confirmed,  ///< against it, and the previous frame's held reversal agrees
  held,       ///< against it with nothing to say the car came through standstill: not a measurement yet
};

/// A velocity reverses through standstill. A pair velocity `v_pair_mps` of
/// frame `index` (t_mid_ns, dt_s after the previous frame) pointing more
/// than 90 deg from the last direction whose sign was measured (within
/// continuity_max_age_s) is taken when the previous frame measured a speed
/// it follows (follows_last_velocity's bound: a slow car), or when the
/// previous frame's held reversal agrees (within the same bound); else it is
/// held. On ground that repeats (a tiled photograph, grooved concrete) a
/// shift past pair_max_shift_px matches the repeat and reads as a slow car
/// going the other way; frames without a speed between the last one and it
/// leave the acceleration bound too wide to refuse it.
Reversal judge_reversal(const MotionMemory& m, Vec2 v_pair_mps, std::int64_t index, std::int64_t t_mid_ns,
                        double dt_s, const GvsEstimatorSettings& set);

/// After a pair attempt of frame `index`: a held reversal is kept for the
/// next frame's judge_reversal, anything else forgets it.
void note_reversal(MotionMemory& m, Reversal r, Vec2 v_pair_mps, std::int64_t index);

/// What a single-frame analysis tells the frames after it.
struct SingleFrameNote {
  bool axis_measured = false;  ///< `anisotropy` was measured (not a dark frame before any pattern is learnt)
  double anisotropy = 0.0;
  bool dark = false;      ///< the spectrum was taken without the sensor's pixel pattern
  bool too_long = false;  ///< the streak outgrew the frame: the speed is at least speed_floor_mps
  double speed_floor_mps = 0.0;
};

/// After a single-frame analysis of the frame at t_mid_ns.
void note_single(MotionMemory& m, const SingleFrameNote& note, std::int64_t t_mid_ns);

/// What one frame adds to the tracking state besides its estimate.
struct FrameOutcome {
  bool sign_known = false;        ///< the estimate's sign was measured (SignChoice::known, or a pair)
  HalfSpectra* halves = nullptr;  ///< this frame's half spectra (a pair was tried), kept for the next
  bool single_tried = false;      ///< a single-frame analysis ran on this frame
};

/// Once per frame, after its estimate `e`: keep the frame as the previous
/// one (with its half spectra, if taken), `e` as the last estimate, and its
/// speed and direction when it measured them (quality > 0).
void update_tracking(TrackingState& t, const FrameView& frame, std::int64_t t_mid_ns, double mean_grey,
                     const VelocityEstimate& e, const FrameOutcome& outcome);

/// A frame that could not be measured (dark, saturated, ...): no previous
/// frame for the next one, and `e` is the last estimate.
void note_unusable_frame(TrackingState& t, const VelocityEstimate& e);

/// Forget all history and everything learnt (gap, restart, wrong frame size).
void forget_tracking(TrackingState& t);

}  // namespace gvs::dsp
