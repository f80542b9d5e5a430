// Reading and writing gvs-dataset/1 folders (shared/spec/dataset-format.md).
#pragma once

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include <opencv2/core/mat.hpp>

#include "gvs/core/frame.hpp"

namespace gvs::drivers {

/// A dataset that cannot be read. The message names the file and the line or
/// key, and says what is wrong.
class DatasetError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// camera.json
struct CameraInfo {
  core::CameraGeometry geometry;
  std::string description;
  /// Simulated runs: the ground rendered ("procedural" or
  /// "photo:FILE:MM_PER_PIXEL", key "ground"); empty: not recorded (camera runs).
  std::string ground;
};

/// One row of frames.csv.
struct FrameRecord {
  std::int64_t index = 0;
  std::string file;  ///< relative to the dataset folder
  std::int64_t t_ns = 0;
  core::ExposurePlan exposure;
};

/// One row of truth.csv: sensor velocity at mid-exposure, vehicle axes.
struct TruthRecord {
  std::int64_t index = 0;
  std::int64_t t_ns = 0;  ///< mid-exposure time
  double vx_mps = 0.0;
  double vy_mps = 0.0;
  double speed_mps = 0.0;
  std::optional<double> direction_deg;  ///< empty below 0.01 m/s
  double yaw_rate_dps = 0.0;
};

/// Parses the `pulses` column ("0:20|400:20", empty = continuous). Throws
/// std::invalid_argument with a message saying what is wrong.
core::ExposurePlan parse_pulses(const std::string& text, double exposure_us);
/// Formats pulses the way frames.csv stores them (empty when continuous).
std::string format_pulses(const core::ExposurePlan& plan);

/// Reads a dataset folder. The constructor reads and checks camera.json,
/// frames.csv and truth.csv (if present); images are read on demand.
class DatasetReader {
 public:
  explicit DatasetReader(const std::filesystem::path& folder);

  [[nodiscard]] const std::filesystem::path& folder() const { return folder_; }
  [[nodiscard]] const CameraInfo& camera() const { return camera_; }
  [[nodiscard]] const std::vector<FrameRecord>& frames() const { return frames_; }
  [[nodiscard]] const std::vector<TruthRecord>& truth() const { return truth_; }
  [[nodiscard]] bool has_truth() const { return !truth_.empty(); }

  /// Reads frame `i` (position in frames(), not its index) as 8-bit gray,
  /// converting colour and 16-bit PNGs. Throws DatasetError naming the file
  /// when it is missing, unreadable or truncated.
  [[nodiscard]] cv::Mat load_gray(std::size_t i) const;

 private:
  std::filesystem::path folder_;
  CameraInfo camera_;
  std::vector<FrameRecord> frames_;
  std::vector<TruthRecord> truth_;
};

/// Writes a dataset folder: camera.json at construction, then one frame (and
/// optionally its truth row) at a time. Files are flushed by close() or the
/// destructor.
class DatasetWriter {
 public:
  DatasetWriter(const std::filesystem::path& folder, const CameraInfo& camera, bool with_truth);
  ~DatasetWriter();
  DatasetWriter(const DatasetWriter&) = delete;
  DatasetWriter& operator=(const DatasetWriter&) = delete;
  DatasetWriter(DatasetWriter&&) = delete;
  DatasetWriter& operator=(DatasetWriter&&) = delete;

  /// Writes `gray` as frames/NNNNNN.png and its row; `record.file` is filled in.
  void write_frame(const cv::Mat& gray, FrameRecord record);
  void write_truth(const TruthRecord& truth);
  void close();

 private:
  std::filesystem::path folder_;
  std::ofstream frames_csv_;
  std::ofstream truth_csv_;
  bool with_truth_;
};

}  // namespace gvs::drivers
