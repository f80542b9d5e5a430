// The "gvs" estimator's measurements. Each is a function of its inputs (the
// frame, or the frame and the previous one; the settings; the tracking
// state it reads, gvs_tracking.hpp) and preallocated working buffers, and
// returns a typed result; GvsEstimator picks one per frame and updates the
// tracking state from its result (docs/estimator.md, "Structure").
//
//   check_still           previous and this frame identical up to noise, and sharp   gvs_still.cpp
//   analyse_pair          previous and this frame overlap: velocity and yaw rate     gvs_pair.cpp
//   analyse_streak        one blurred frame: streak axis and length                  gvs_single.cpp, streak_end.cpp
//   analyse_double_pulse  one frame lit twice: displacement between the two images  gvs_double.cpp
#pragma once

#include <cstdint>

#include <opencv2/core/mat.hpp>
#include <opencv2/core/types.hpp>

#include "gvs/dsp/blur_analysis.hpp"
#include "gvs/dsp/vocabulary.hpp"
#include "gvs/dsp/gvs_settings.hpp"
#include "gvs/dsp/gvs_tracking.hpp"
#include "gvs/dsp/phase_correlation.hpp"
#include "gvs/dsp/spectrum.hpp"

namespace gvs::dsp {

// --- standstill ---

struct StillCheck {
  bool still = false;
  /// mean((g1 - k g0)^2) / (2 var(g1)): ~0 for the same ground, ~1 for other ground.
  double ratio = 1.0;
};

/// `gray` (mean grey `mean_grey`) and the previous frame show the same
/// ground, unmoved: they differ by little more than the temporal noise, the
/// frame holds texture rather than only the sensor's pattern, and both are
/// sharp (not two frames smeared alike by a long streak).
StillCheck check_still(const cv::Mat& gray, double mean_grey, const PreviousFrame& previous,
                       const GvsEstimatorSettings& set);

// --- frame pairs ---

/// Working buffers of analyse_pair (made once; no meaning between frames).
struct PairWorkspace {
  explicit PairWorkspace(cv::Size frame_size);

  cv::Rect left;   ///< half windows, 5/8 of the width each (they overlap), full height
  cv::Rect right;
  WindowedSpectrum half_spectrum;
  PhaseCorrelator correlator;
  HalfSpectra current;   ///< this frame's (update_tracking keeps them for the next frame)
  HalfSpectra previous;  ///< the previous frame's, when its kept ones do not fit
};

struct PairResult {
  VelocityEstimate estimate;  ///< "pair", or "no-match" with quality 0
  /// The halves matched well enough (pair_min_quality) and the turn is
  /// plausible: the sign is known, and v_pair_mps is the next pair's slope
  /// (note_pair).
  bool matched = false;
  /// Mean velocity between the two frames' light centres, before the lag
  /// compensation (also of a held reversal).
  Vec2 v_pair_mps{};
  /// Against the measured direction? A held one is no match (judge_reversal).
  Reversal reversal = Reversal::none;
};

/// Phase correlation of the two half windows of `frame` with those of the
/// previous frame, dt_s earlier. Takes this frame's half spectra into
/// ws.current.
PairResult analyse_pair(const FrameView& frame, std::int64_t t_mid_ns, double dt_s, double mean_grey,
                        const TrackingState& track, const CameraGeometry& cam,
                        const GvsEstimatorSettings& set, PairWorkspace& ws);

// --- one frame ---

/// Working buffers of analyse_streak and analyse_double_pulse (made once;
/// no meaning between frames).
struct SpectrumWorkspace {
  explicit SpectrumWorkspace(cv::Size frame_size);

  WindowedSpectrum tukey;  ///< the spectrum every one-frame analysis starts from
  /// Hann-windowed (taper 1), only to check a streak length found without a
  /// recent speed (circular aliasing, analyse_streak).
  WindowedSpectrum hann;
  BlurAnalyzer blur;
  cv::Mat spectrum;       ///< CV_32FC2, from `tukey`: columns 0 .. cols/2 (BlurAnalyzer reads no more)
  cv::Mat hann_spectrum;  ///< CV_32FC2, from `hann`: the same columns
  BlurAnalyzer::RingGain ring_gain{};
};

struct StreakResult {
  /// "blur-*" (axis and speed, or axis only), "streak-*" (too long: axis
  /// only), "short-streak", "no-texture" or "no-match" (quality 0).
  VelocityEstimate estimate;
  bool sign_known = false;  ///< SignChoice::known of its direction
  SingleFrameNote note;     ///< for the frames after it (note_single)
};

/// The motion blur of one frame: streak axis from the power spectrum's
/// orientation, streak length from the derivative's autocorrelation, searched
/// around the last speed when it is recent (track.motion).
StreakResult analyse_streak(const FrameView& frame, std::int64_t t_mid_ns, double mean_grey,
                            const TrackingState& track, const CameraGeometry& cam,
                            const GvsEstimatorSettings& set, SpectrumWorkspace& ws);

struct DoublePulseResult {
  VelocityEstimate estimate;  ///< "dpiv-*", or "no-match" with quality 0
  bool sign_known = false;    ///< SignChoice::known of its direction
};

/// A frame lit by two pulses: the displacement between its two images (the
/// autocorrelation's side peak) over the time between the pulses' centres.
DoublePulseResult analyse_double_pulse(const FrameView& frame, std::int64_t t_mid_ns,
                                       const TrackingState& track, const CameraGeometry& cam,
                                       const GvsEstimatorSettings& set, SpectrumWorkspace& ws);

/// Fills direction (and vx, vy, speed when `with_speed`) from a vehicle-axes velocity.
void set_velocity(VelocityEstimate& e, Vec2 v, bool with_speed);

}  // namespace gvs::dsp
