// Accuracy of an estimates CSV against a dataset's truth, per speed band
// (what `gvs eval` prints).
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "gvs/drivers/dataset.hpp"
#include "gvs/drivers/estimates_csv.hpp"

namespace gvs::eval {

/// Summary statistics of a set of errors.
struct ErrorStats {
  std::size_t count = 0;
  double mean = 0.0;
  double std = 0.0;
  double rms = 0.0;
  double max_abs = 0.0;
};
ErrorStats error_stats(const std::vector<double>& errors);

struct BandAccuracy {
  double lo_kmh = 0.0;
  double hi_kmh = 0.0;
  std::size_t frames = 0;               ///< truth frames in the band
  std::size_t moving_frames = 0;        ///< of those, truth speed >= 0.5 km/h
  std::size_t with_direction = 0;       ///< moving frames with a direction estimate
  std::size_t with_speed = 0;           ///< frames with a speed estimate
  /// Of with_direction and with_speed, those at the bus's default quality
  /// (kBusMinQuality) or above: what the ECU is sent as valid.
  std::size_t valid_direction = 0;
  std::size_t valid_speed = 0;
  ErrorStats direction_deg;             ///< estimate - truth, wrapped to (-180, 180]
  ErrorStats speed_pct;                 ///< (estimate - truth) / truth * 100, truth >= 0.5 km/h
  ErrorStats yaw_rate_dps;              ///< where both exist
  /// Speeds off by more than kWrongSpeedPct where the truth is at least
  /// kWrongSpeedMinKmh: a wrong value on the bus (must be 0).
  std::size_t speed_off = 0;
};

/// Truth below this speed is not "moving": direction and % speed errors are not meaningful.
constexpr double kMovingKmh = 0.5;
constexpr double kWrongSpeedPct = 5.0;
constexpr double kWrongSpeedMinKmh = 1.0;
/// gvsd's default `[can] min_quality` (can::ValidityRule): a lower quality
/// goes out with its Valid bits 0.
extern const double kBusMinQuality;

/// The thesis's summary of a constant-direction run (its Tab. 4.3).
struct ConstantDirectionSummary {
  double truth_deg = 0.0;
  std::size_t count = 0;
  double mean = 0.0;
  double std = 0.0;
  double mode = 0.0;  ///< centre of the most populated 0.1-deg bin
  double min = 0.0;
  double max = 0.0;
};

struct AccuracyReport {
  std::vector<BandAccuracy> bands;
  BandAccuracy all;
  std::size_t standstill_frames = 0;      ///< truth speed < 0.01 m/s
  std::size_t standstill_with_speed = 0;
  double standstill_speed_max_abs_mps = 0.0;
  std::size_t standstill_with_direction = 0;  ///< should be 0
  std::size_t estimates_without_truth = 0;
  std::size_t truth_without_estimate = 0;
  std::optional<ConstantDirectionSummary> constant_direction;
};

/// The speed bands of the accuracy targets (docs/accuracy.md), km/h.
const std::vector<std::pair<double, double>>& speed_bands_kmh();

/// Compares estimates with truth, matching rows by frame index.
AccuracyReport evaluate_accuracy(const std::vector<drivers::TruthRecord>& truth,
                                 const std::vector<drivers::EstimateRow>& estimates);

/// The table `gvs eval` prints.
std::string format_accuracy_table(const AccuracyReport& report);
/// The same as JSON (for scripts that aggregate Monte Carlo runs).
std::string format_accuracy_json(const AccuracyReport& report);

}  // namespace gvs::eval
