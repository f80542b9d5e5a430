// Why frames have no speed: the estimates' method words read against the
// truth and the exposure (what `gvs eval`, `gvs replay`, the eval plot and
// `gvs snapshot` say when a speed is missing).
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "gvs/core/frame.hpp"
#include "gvs/core/method.hpp"
#include "gvs/drivers/dataset.hpp"
#include "gvs/drivers/estimates_csv.hpp"

namespace gvs::eval {

/// What the truth and the exposure say about the frames of one cause.
enum class SpeedGapCause {
  streak_too_long,   ///< speed x light time is longer than the frame can measure
  streak_too_short,  ///< ... shorter than the estimator measures a length from
  streak_unclear,    ///< a streak of a measurable length whose end was not found
  no_estimate_row,   ///< the estimates CSV has no row for the frame
  other,             ///< the method's own description says why
};

/// Moving frames without a speed that share a cause (and, for `other`, a method).
struct SpeedGap {
  SpeedGapCause cause = SpeedGapCause::other;
  std::vector<std::pair<core::Method, std::size_t>> methods;  ///< method words and their frame counts
  std::vector<std::int64_t> indices;                           ///< the frames, in order
  bool continuous = false;           ///< some of the frames were exposed continuously
  bool pulsed = false;               ///< ... some with light pulses
  double speed_kmh_min = 0.0, speed_kmh_max = 0.0;        ///< truth
  double light_us_min = 0.0, light_us_max = 0.0;          ///< ExposurePlan::lit_time_us
  double streak_px_min = 0.0, streak_px_max = 0.0;        ///< truth speed x light time / mm_per_px
  double measurable_px_min = 0.0, measurable_px_max = 0.0;  ///< longest streak the frame measures along it
};

struct SpeedGapReport {
  std::size_t moving_frames = 0;  ///< truth at least 0.5 km/h
  std::size_t without_speed = 0;  ///< of those, no speed estimate
  double mm_per_px = 0.0;
  int width_px = 0, height_px = 0;
  /// The first frame exposed with light pulses (a closed double-pulse loop
  /// starts on continuous exposures until it has a speed).
  std::optional<std::int64_t> first_pulsed_index;
  std::vector<SpeedGap> gaps;  ///< most frames first
};

/// The moving frames of `dataset` (which must have truth) without a speed in
/// `estimates`, grouped by cause.
SpeedGapReport find_speed_gaps(const drivers::DatasetReader& dataset, const std::vector<drivers::EstimateRow>& estimates);

/// "no speed on N of M moving frames:" and one line per gap saying why and
/// what would measure it; empty when every moving frame has a speed.
std::string format_speed_gaps(const SpeedGapReport& report);

/// One frame's reason (gvs snapshot): its method, and where the truth speed
/// is known the streak it implies at this exposure; empty when `e` has a speed.
std::string why_no_speed(const core::VelocityEstimate& e, const core::ExposurePlan& exposure,
                         const core::CameraGeometry& camera, std::optional<drivers::TruthRecord> truth);

}  // namespace gvs::eval
