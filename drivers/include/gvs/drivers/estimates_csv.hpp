// The estimates CSV a replay run writes (shared/spec/dataset-format.md):
// index,t_ns,vx_mps,vy_mps,speed_mps,direction_deg,yaw_rate_dps,quality,method
#pragma once

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "gvs/dsp/estimate.hpp"

namespace gvs::drivers {

/// One parsed row; `method` owns its text (VelocityEstimate::method points at
/// a literal, which a file cannot provide).
struct EstimateRow {
  dsp::VelocityEstimate estimate;
  std::string method;
};

class EstimatesCsvWriter {
 public:
  explicit EstimatesCsvWriter(const std::filesystem::path& file);
  void write(const dsp::VelocityEstimate& e);
  void close();

 private:
  std::filesystem::path file_;
  std::ofstream out_;
};

/// Reads an estimates CSV. Throws DatasetError naming file and line.
std::vector<EstimateRow> read_estimates_csv(const std::filesystem::path& file);

/// Formats one row (no newline), as EstimatesCsvWriter writes it.
std::string format_estimate_row(const dsp::VelocityEstimate& e);

}  // namespace gvs::drivers
