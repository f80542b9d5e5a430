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
#include "gvs/core/laser_geometry.hpp"

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
  /// Nominal height of the camera's optical centre above the ground, mm,
  /// where mm_per_px holds (key "height_mm", written by the simulator);
  /// empty: not recorded.
  std::optional<double> height_mm;
  /// The head's laser dots (optional key "lasers"; count 0: none, and the
  /// key is not written).
  core::LaserGeometry lasers;
};

/// One row of frames.csv.
struct FrameRecord {
  std::int64_t index = 0;
  std::string file;  ///< relative to the dataset folder
  std::int64_t t_ns = 0;
  core::ExposurePlan exposure;
};

/// One row of truth.csv: sensor velocity at mid-exposure, vehicle axes, and
/// where the run has them, the body's height and attitude then.
struct TruthRecord {
  std::int64_t index = 0;
  std::int64_t t_ns = 0;  ///< mid-exposure time
  double vx_mps = 0.0;
  double vy_mps = 0.0;
  double speed_mps = 0.0;
  std::optional<double> direction_deg;  ///< empty below 0.01 m/s
  double yaw_rate_dps = 0.0;
  /// Optical centre to the ground along the vehicle's z axis; empty (no
  /// column or an empty field): the nominal height of camera.json.
  std::optional<double> height_mm;
  std::optional<double> pitch_deg;  ///< ISO 8855: positive = nose down; empty: level
  std::optional<double> roll_deg;   ///< ISO 8855: positive = right side down; empty: level
};

/// camera.json's "lasers" object for `lasers`, as JSON text.
std::string laser_geometry_json_text(const core::LaserGeometry& lasers);
/// The laser geometry in `file`: either the "lasers" object itself (what
/// `gvs calibrate height --out` writes) or a camera.json that holds one.
/// Throws DatasetError naming the file and what is wrong (unreadable, not
/// JSON, no beams, a key out of range).
core::LaserGeometry load_laser_geometry(const std::filesystem::path& file);

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
/// destructor. `with_body_pose`: truth.csv has the columns height_mm,
/// pitch_deg, roll_deg after the seven standard ones (a record without a
/// value leaves its field empty).
class DatasetWriter {
 public:
  DatasetWriter(const std::filesystem::path& folder, const CameraInfo& camera, bool with_truth,
                bool with_body_pose = false);
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
  bool with_body_pose_;
};

}  // namespace gvs::drivers
