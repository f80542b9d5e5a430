// The streak end of one blurred frame (private to dsp/src/gvs): where it is
// looked for (streak_search), and whether it is clear enough for the axis
// and the speed (find_streak_end).
#pragma once

#include <cstdint>

#include <opencv2/core.hpp>

#include "gvs/dsp/blur_analysis.hpp"
#include "gvs/dsp/gvs_analysis.hpp"

namespace gvs::dsp {

/// The spectrum of `gray` through `with` into `spectrum`, without the sensor's
/// pixel pattern (`pattern_out`) or else its column pattern (once learnt).
inline void take_spectrum(WindowedSpectrum& with, const cv::Mat& gray, cv::Mat& spectrum,
                          const SensorPattern& pattern, bool pattern_out) {
  if (pattern_out) {
    with.compute(gray, spectrum, pattern.pixels());
  } else {
    with.compute(gray, spectrum, pattern.columns());
  }
}

/// Where the streak end is looked for, and how clear it must be.
struct StreakSearch {
  double lo_px = 0.0;
  double hi_px = 0.0;
  double expected_px = 0.0;  ///< L predicted from the recent speed (0: none)
  double min_significance = 0.0;
  double min_length_px = 0.0;
  double max_background = 0.0;
  /// How far the power cepstrum looks: every length the recent speed allows,
  /// or (no recent speed) up to cepstrum_max_streak_fraction of the frame.
  double cepstrum_hi_px = 0.0;
  /// The cepstrum's range holds every length the recent speed allows, or
  /// there is no recent speed: its deepest end is a witness for the end.
  bool cepstrum_sees_all = true;
  /// No recent speed, but one within reacquire_memory_s whose lengths now
  /// (+-speed_window_fraction, +-max_accel_mps2 since) are all within the
  /// cepstrum's reach: an end in [reacquire_lo_px, reacquire_hi_px] that
  /// the cepstrum confirms needs only the tracked gates.
  bool reacquire = false;
  double reacquire_lo_px = 0.0;
  double reacquire_hi_px = 0.0;
};

/// Around L = v T / s from the last measured speed (recent by time, widened
/// for +-max_accel), because the texture's own grain can mimic a streak end;
/// everywhere, with a stricter significance and background, without a
/// recent speed. `extent_px`: the frame's extent along the axis; `t_s`:
/// light time.
StreakSearch streak_search(const MotionMemory& m, std::int64_t index, std::int64_t t_mid_ns, double extent_px,
                           double t_s, double m_per_px, const GvsEstimatorSettings& set);

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

/// The streak end along `axis` within `search`, and what it may give.
StreakEnd find_streak_end(const cv::Mat& gray, const StreakAxis& axis, bool axis_refined,
                          const StreakSearch& search, const SensorPattern& pattern, bool pattern_out,
                          bool well_lit, const GvsEstimatorSettings& set, SpectrumWorkspace& ws);

}  // namespace gvs::dsp
