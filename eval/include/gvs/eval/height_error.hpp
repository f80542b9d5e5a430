// The speed error against the camera's height (what `gvs eval` adds for a
// dataset whose truth has height_mm: a run with body motion). The ground
// scale is proportional to the height, so an estimator that assumes the
// nominal height H0 reads a speed off by H0 / H - 1 (docs/accuracy.md,
// "Speed against heave").
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "gvs/drivers/dataset.hpp"
#include "gvs/drivers/estimates_csv.hpp"
#include "gvs/eval/accuracy.hpp"

namespace gvs::eval {

/// Moving frames with a speed whose height error (H - H0) falls in [lo, hi).
struct HeightBin {
  double lo_mm = 0.0;
  double hi_mm = 0.0;
  ErrorStats height_error_mm;  ///< H - H0 (its mean: where the bin's frames are)
  ErrorStats speed_pct;        ///< (estimate - truth) / truth * 100
  ErrorStats scale_pct;        ///< (H0 / H - 1) * 100: the error the scale alone makes
  /// The speed error with the scale corrected by the true height,
  /// (estimate H / H0 - truth) / truth * 100: what is left for a perfect
  /// height measurement.
  ErrorStats corrected_pct;
};

struct HeightReport {
  double nominal_mm = 0.0;
  std::vector<HeightBin> bins;
  HeightBin all;
  /// Least-squares slope of the speed error against the height error, % per mm.
  double slope_pct_per_mm = 0.0;
};

/// The bins' edges, mm of height error: ..., -4, -2, -0.5, 0.5, 2, 4, ... up to the kerb's 15 mm.
const std::vector<double>& height_bin_edges_mm();

/// Empty when no truth row has a height. `nominal_mm`: camera.json's
/// height_mm (docs: 60 mm when the dataset does not say).
std::optional<HeightReport> evaluate_speed_vs_height(const std::vector<drivers::TruthRecord>& truth,
                                                     const std::vector<drivers::EstimateRow>& estimates,
                                                     double nominal_mm);

std::string format_height_table(const HeightReport& report);

}  // namespace gvs::eval
