// The estimates CSV a replay run writes (shared/spec/dataset-format.md):
// index,t_ns,vx_mps,vy_mps,speed_mps,direction_deg,yaw_rate_dps,quality,method
#pragma once

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "gvs/core/estimate.hpp"

namespace gvs::drivers {

/// One parsed row. The `method` word maps back through core::kMethods; a word
/// the table lacks (a file from another estimator: the format allows any
/// word) reads as core::Method::unknown.
struct EstimateRow {
  core::VelocityEstimate estimate;
};

class EstimatesCsvWriter {
 public:
  explicit EstimatesCsvWriter(const std::filesystem::path& file);
  void write(const core::VelocityEstimate& e);
  void close();

 private:
  std::filesystem::path file_;
  std::ofstream out_;
};

/// Reads an estimates CSV. Throws DatasetError naming file and line.
std::vector<EstimateRow> read_estimates_csv(const std::filesystem::path& file);

/// Formats one row (no newline), as EstimatesCsvWriter writes it.
std::string format_estimate_row(const core::VelocityEstimate& e);

}  // namespace gvs::drivers
