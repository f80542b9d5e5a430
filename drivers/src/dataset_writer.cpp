// Writes gvs-dataset/1 folders (the simulator's and the recorder's output).
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "laser_json.hpp"

#include "gvs/drivers/dataset.hpp"
#include "gvs/drivers/png_file.hpp"

namespace gvs::drivers {

namespace fs = std::filesystem;

namespace {

std::string format_number(double v, int decimals) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*f", decimals, v);
  // Trim trailing zeros (and a trailing point) so "3000.000" reads "3000".
  std::string s(buf);
  if (s.find('.') != std::string::npos) {
    while (!s.empty() && s.back() == '0') s.pop_back();
    if (!s.empty() && s.back() == '.') s.pop_back();
  }
  if (s == "-0") s = "0";
  return s;
}

std::ofstream open_for_writing(const fs::path& file) {
  std::ofstream out(file, std::ios::trunc);
  if (!out) throw DatasetError(file.string() + ": cannot create (check the folder exists and is writable)");
  return out;
}

}  // namespace

std::string format_pulses(const core::ExposurePlan& plan) {
  std::string s;
  for (std::size_t i = 0; i < plan.pulse_count; ++i) {
    if (i > 0) s += '|';
    s += format_number(plan.pulses[i].start_us, 3) + ':' + format_number(plan.pulses[i].duration_us, 3);
  }
  return s;
}

DatasetWriter::DatasetWriter(const fs::path& folder, const CameraInfo& camera, bool with_truth,
                             bool with_body_pose)
    : folder_(folder), with_truth_(with_truth), with_body_pose_(with_body_pose) {
  std::error_code ec;
  fs::create_directories(folder / "frames", ec);
  if (ec) throw DatasetError((folder / "frames").string() + ": cannot create folder: " + ec.message());

  nlohmann::ordered_json j;
  j["format"] = "gvs-dataset/1";
  j["width"] = camera.geometry.width_px;
  j["height"] = camera.geometry.height_px;
  j["mm_per_px"] = camera.geometry.mm_per_px;
  j["mount_yaw_deg"] = camera.geometry.mount_yaw_deg;
  j["description"] = camera.description;
  if (!camera.ground.empty()) j["ground"] = camera.ground;
  if (camera.height_mm) j["height_mm"] = *camera.height_mm;
  if (camera.lasers.enabled()) j["lasers"] = detail::laser_geometry_json(camera.lasers);
  std::ofstream cam = open_for_writing(folder / "camera.json");
  cam << j.dump(2) << '\n';

  frames_csv_ = open_for_writing(folder / "frames.csv");
  frames_csv_ << "index,file,t_ns,exposure_us,pulses\n";
  if (with_truth_) {
    truth_csv_ = open_for_writing(folder / "truth.csv");
    truth_csv_ << "index,t_ns,vx_mps,vy_mps,speed_mps,direction_deg,yaw_rate_dps"
               << (with_body_pose_ ? ",height_mm,pitch_deg,roll_deg\n" : "\n");
  } else {
    std::error_code ignore;
    fs::remove(folder / "truth.csv", ignore);
  }
}

DatasetWriter::~DatasetWriter() {
  try {
    close();
  } catch (...) {  // NOLINT(bugprone-empty-catch): a destructor must not throw
  }
}

void DatasetWriter::write_frame(const cv::Mat& gray, FrameRecord record) {
  char name[32];
  std::snprintf(name, sizeof name, "frames/%06lld.png", static_cast<long long>(record.index));
  record.file = name;
  const fs::path file = folder_ / record.file;
  const std::string error = write_png(file.string(), gray, 1);
  if (!error.empty()) throw DatasetError(file.string() + ": " + error);
  frames_csv_ << record.index << ',' << record.file << ',' << record.t_ns << ','
              << format_number(record.exposure.exposure_us, 3) << ',' << format_pulses(record.exposure) << '\n';
  if (!frames_csv_) throw DatasetError((folder_ / "frames.csv").string() + ": write failed (disk full?)");
}

void DatasetWriter::write_truth(const TruthRecord& t) {
  if (!with_truth_) return;
  truth_csv_ << t.index << ',' << t.t_ns << ',' << format_number(t.vx_mps, 6) << ','
             << format_number(t.vy_mps, 6) << ',' << format_number(t.speed_mps, 6) << ','
             << (t.direction_deg ? format_number(*t.direction_deg, 6) : std::string()) << ','
             << (std::isfinite(t.yaw_rate_dps) ? format_number(t.yaw_rate_dps, 6) : std::string());
  if (with_body_pose_) {
    const auto optional = [](const std::optional<double>& v) {
      return v && std::isfinite(*v) ? format_number(*v, 6) : std::string();
    };
    truth_csv_ << ',' << optional(t.height_mm) << ',' << optional(t.pitch_deg) << ',' << optional(t.roll_deg);
  }
  truth_csv_ << '\n';
  if (!truth_csv_) throw DatasetError((folder_ / "truth.csv").string() + ": write failed (disk full?)");
}

void DatasetWriter::close() {
  if (frames_csv_.is_open()) frames_csv_.close();
  if (truth_csv_.is_open()) truth_csv_.close();
}

}  // namespace gvs::drivers
