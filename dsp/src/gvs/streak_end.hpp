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
  /// The longest streak the recent speed allows is beyond max_px: the end
  /// may lie outside the window.
  bool clipped = false;
};

/// Around L = v T / s from the last measured speed (recent by time, widened
/// for +-max_accel), because the texture's own grain can mimic a streak end;
/// everywhere, with a stricter significance and background, without a
/// recent speed. `max_px`: the longest measurable streak; `t_s`: light time.
StreakSearch streak_search(const MotionMemory& m, std::int64_t index, std::int64_t t_mid_ns, double max_px,
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
