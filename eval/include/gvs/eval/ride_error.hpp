// The measured ride height (laser dots) against the truth: what `gvs eval
// --ride` prints. The estimates CSV of shared/spec/dataset-format.md has a
// fixed set of columns and no room for more, so `gvs replay --ride FILE`
// writes the measured height, pitch and roll to a file of their own:
//   index,t_ns,height_mm,pitch_deg,roll_deg,dots_found,scale_source
// (empty fields where nothing was measured; scale_source: nominal,
// laser_dots, external).
#pragma once

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <optional>
#include <string>
#include <vector>

#include "gvs/core/estimate.hpp"
#include "gvs/drivers/dataset.hpp"
#include "gvs/drivers/estimates_csv.hpp"
#include "gvs/eval/accuracy.hpp"

namespace gvs::eval {

struct RideRow {
  std::int64_t index = 0;
  std::int64_t t_ns = 0;
  core::RideHeight ride;
  int dots_found = 0;
  core::ScaleSource scale_source = core::ScaleSource::nominal;
};

class RideCsvWriter {
 public:
  /// Throws std::runtime_error naming the file when it cannot be written.
  explicit RideCsvWriter(const std::filesystem::path& file);
  void write(const core::VelocityEstimate& e, int dots_found);
  void close();

 private:
  std::filesystem::path file_;
  std::ofstream out_;
};

/// Throws std::runtime_error naming the file and line when it is malformed.
std::vector<RideRow> read_ride_csv(const std::filesystem::path& file);

struct RideReport {
  std::size_t frames = 0;       ///< truth rows with a height
  std::size_t with_height = 0;  ///< of those, a measured height
  std::size_t with_pitch = 0;
  std::size_t with_roll = 0;
  ErrorStats height_mm;  ///< measured - truth
  ErrorStats pitch_deg;
  ErrorStats roll_deg;
  /// Measured frames off by more than kWrongHeightMm or kWrongTiltDeg:
  /// wrong values, not noise (the targets are 0.05 mm and 0.05 deg RMS).
  std::size_t wrong = 0;
  static constexpr double kWrongHeightMm = 0.15;
  static constexpr double kWrongTiltDeg = 0.5;
  /// Speed error (%) of moving frames whose speed was scaled by the dots,
  /// and of those left at the nominal scale (dots not found).
  ErrorStats speed_pct_dots;
  ErrorStats speed_pct_nominal;
  /// The share of the frames with a height (or with `measured` of them).
  [[nodiscard]] double coverage() const { return coverage(with_height); }
  [[nodiscard]] double coverage(std::size_t measured) const {
    return frames > 0 ? static_cast<double>(measured) / static_cast<double>(frames) : 0.0;
  }
};

/// Empty when the truth has no height (a run without body motion takes the
/// nominal height and a level ground as its truth: `nominal_mm`).
RideReport evaluate_ride(const std::vector<drivers::TruthRecord>& truth, const std::vector<RideRow>& rides,
                         const std::vector<drivers::EstimateRow>& estimates, double nominal_mm);
std::string format_ride_table(const RideReport& report);

}  // namespace gvs::eval
