// Reads and checks a gvs-dataset/1 folder. Every error names the file and the
// line or key, and what is wrong.
#include <cmath>
#include <fstream>
#include <sstream>
#include <string>

#include <nlohmann/json.hpp>
#include <opencv2/imgproc.hpp>

#include "csv_line.hpp"
#include "laser_json.hpp"
#include "gvs/drivers/dataset.hpp"
#include "gvs/drivers/png_file.hpp"

namespace gvs::drivers {

namespace fs = std::filesystem;
using detail::Columns;
using detail::parse_double;
using detail::parse_int;
using detail::split_csv;

namespace {

[[noreturn]] void fail(const fs::path& file, const std::string& what) {
  throw DatasetError(file.string() + ": " + what);
}

[[noreturn]] void fail_line(const fs::path& file, std::size_t line, const std::string& what) {
  throw DatasetError(file.string() + ":" + std::to_string(line) + ": " + what);
}

CameraInfo read_camera_json(const fs::path& file) {
  std::ifstream in(file);
  if (!in) fail(file, "cannot open (every dataset needs camera.json; see shared/spec/dataset-format.md)");
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception& e) {
    fail(file, std::string("not valid JSON: ") + e.what());
  }
  if (!j.is_object()) fail(file, "must hold a JSON object");

  auto require = [&](const char* key) -> const nlohmann::json& {
    if (!j.contains(key)) fail(file, std::string("missing required key '") + key + "'");
    return j.at(key);
  };
  auto number = [&](const char* key) -> double {
    const nlohmann::json& v = require(key);
    if (!v.is_number()) fail(file, std::string("key '") + key + "' must be a number");
    return v.get<double>();
  };
  auto positive_int = [&](const char* key) -> int {
    const nlohmann::json& v = require(key);
    if (!v.is_number_integer() || v.get<long long>() <= 0 || v.get<long long>() > 100000) {
      fail(file, std::string("key '") + key + "' must be a positive whole number of pixels");
    }
    return static_cast<int>(v.get<long long>());
  };

  const nlohmann::json& format = require("format");
  if (!format.is_string() || format.get<std::string>() != "gvs-dataset/1") {
    fail(file, "key 'format' must be \"gvs-dataset/1\" (this reader knows version 1 only)");
  }
  CameraInfo cam;
  cam.geometry.width_px = positive_int("width");
  cam.geometry.height_px = positive_int("height");
  cam.geometry.mm_per_px = number("mm_per_px");
  if (!(cam.geometry.mm_per_px > 0.0) || cam.geometry.mm_per_px > 100.0) {
    fail(file, "key 'mm_per_px' must be in (0, 100] mm per pixel");
  }
  cam.geometry.mount_yaw_deg = j.contains("mount_yaw_deg") ? number("mount_yaw_deg") : 0.0;
  if (j.contains("description") && j.at("description").is_string()) {
    cam.description = j.at("description").get<std::string>();
  }
  if (j.contains("ground") && j.at("ground").is_string()) cam.ground = j.at("ground").get<std::string>();
  if (j.contains("height_mm")) {
    cam.height_mm = number("height_mm");
    if (!(*cam.height_mm > 0.0) || *cam.height_mm > 100000.0) fail(file, "key 'height_mm' must be in (0, 100000] mm");
  }
  if (j.contains("lasers")) cam.lasers = detail::laser_geometry_from_json(j.at("lasers"), file);
  return cam;
}

std::vector<FrameRecord> read_frames_csv(const fs::path& file) {
  std::ifstream in(file);
  if (!in) fail(file, "cannot open (every dataset needs frames.csv)");
  std::string line;
  if (!std::getline(in, line)) fail(file, "empty: expected the header 'index,file,t_ns,exposure_us,pulses'");
  const Columns cols = detail::parse_header(line);
  const int c_index = cols.find("index");
  const int c_file = cols.find("file");
  const int c_t = cols.find("t_ns");
  const int c_exp = cols.find("exposure_us");
  const int c_pulses = cols.find("pulses");
  for (auto [c, name] : {std::pair{c_index, "index"}, {c_file, "file"}, {c_t, "t_ns"}, {c_exp, "exposure_us"}}) {
    if (c < 0) fail_line(file, 1, std::string("header lacks the column '") + name + "'");
  }

  std::vector<FrameRecord> frames;
  std::size_t line_no = 1;
  while (std::getline(in, line)) {
    ++line_no;
    if (line.empty() || line == "\r") continue;
    const auto fields = split_csv(line);
    auto field = [&](int c) -> std::string_view {
      if (c < 0) return {};
      if (static_cast<std::size_t>(c) >= fields.size()) {
        if (c == c_pulses) return {};
        fail_line(file, line_no, "too few columns (" + std::to_string(fields.size()) + ")");
      }
      return fields[static_cast<std::size_t>(c)];
    };
    FrameRecord r;
    if (!parse_int(field(c_index), r.index) || r.index < 0) {
      fail_line(file, line_no, "index '" + std::string(field(c_index)) + "' is not a whole number >= 0");
    }
    r.file = std::string(field(c_file));
    if (r.file.empty()) fail_line(file, line_no, "file is empty");
    if (!parse_int(field(c_t), r.t_ns)) {
      fail_line(file, line_no, "t_ns '" + std::string(field(c_t)) + "' is not a whole number of nanoseconds");
    }
    double exposure_us = 0.0;
    if (!parse_double(field(c_exp), exposure_us) || exposure_us <= 0.0) {
      fail_line(file, line_no, "exposure_us '" + std::string(field(c_exp)) + "' must be a number > 0");
    }
    try {
      r.exposure = parse_pulses(std::string(field(c_pulses)), exposure_us);
    } catch (const std::invalid_argument& e) {
      fail_line(file, line_no, std::string("pulses: ") + e.what());
    }
    if (!frames.empty()) {
      if (r.index <= frames.back().index) {
        fail_line(file, line_no, "index " + std::to_string(r.index) + " does not increase (previous " +
                                     std::to_string(frames.back().index) + ")");
      }
      if (r.t_ns <= frames.back().t_ns) {
        fail_line(file, line_no, "t_ns " + std::to_string(r.t_ns) + " goes backwards or repeats (previous " +
                                     std::to_string(frames.back().t_ns) + ")");
      }
    }
    frames.push_back(std::move(r));
  }
  if (frames.empty()) fail(file, "holds no frames");
  return frames;
}

std::vector<TruthRecord> read_truth_csv(const fs::path& file) {
  std::ifstream in(file);
  if (!in) fail(file, "cannot open");
  std::string line;
  if (!std::getline(in, line)) fail(file, "empty: expected a header line");
  const Columns cols = detail::parse_header(line);
  const char* names[] = {"index", "t_ns", "vx_mps", "vy_mps", "speed_mps", "direction_deg", "yaw_rate_dps"};
  int c[7];
  for (int i = 0; i < 7; ++i) {
    c[i] = cols.find(names[i]);
    if (c[i] < 0) fail_line(file, 1, std::string("header lacks the column '") + names[i] + "'");
  }
  // Optional body columns (by name, wherever they are; absent: nominal, level).
  const int c_height = cols.find("height_mm");
  const int c_pitch = cols.find("pitch_deg");
  const int c_roll = cols.find("roll_deg");
  std::vector<TruthRecord> rows;
  std::size_t line_no = 1;
  while (std::getline(in, line)) {
    ++line_no;
    if (line.empty() || line == "\r") continue;
    const auto fields = split_csv(line);
    auto field = [&](int i) -> std::string_view {
      const auto pos = static_cast<std::size_t>(c[i]);
      return pos < fields.size() ? fields[pos] : std::string_view{};
    };
    TruthRecord t;
    if (!parse_int(field(0), t.index)) fail_line(file, line_no, "index is not a whole number");
    if (!parse_int(field(1), t.t_ns)) fail_line(file, line_no, "t_ns is not a whole number");
    if (!parse_double(field(2), t.vx_mps) || !parse_double(field(3), t.vy_mps)) {
      fail_line(file, line_no, "vx_mps and vy_mps must be numbers");
    }
    if (!parse_double(field(4), t.speed_mps)) t.speed_mps = std::hypot(t.vx_mps, t.vy_mps);
    double dir = 0.0;
    if (parse_double(field(5), dir)) t.direction_deg = dir;
    if (!parse_double(field(6), t.yaw_rate_dps)) t.yaw_rate_dps = std::nan("");
    // An empty field (or none) is "not known"; anything else must be a number.
    auto optional = [&](int col, const char* name, std::optional<double>& out) {
      if (col < 0 || static_cast<std::size_t>(col) >= fields.size() || fields[static_cast<std::size_t>(col)].empty())
        return;
      double v = 0.0;
      if (!parse_double(fields[static_cast<std::size_t>(col)], v) || !std::isfinite(v)) {
        fail_line(file, line_no, std::string(name) + " '" + std::string(fields[static_cast<std::size_t>(col)]) +
                                     "' is not a number");
      }
      out = v;
    };
    optional(c_height, "height_mm", t.height_mm);
    optional(c_pitch, "pitch_deg", t.pitch_deg);
    optional(c_roll, "roll_deg", t.roll_deg);
    if (t.height_mm && !(*t.height_mm > 0.0)) fail_line(file, line_no, "height_mm must be > 0");
    if (!rows.empty() && t.index <= rows.back().index) {
      fail_line(file, line_no, "index " + std::to_string(t.index) + " does not increase");
    }
    rows.push_back(t);
  }
  return rows;
}

}  // namespace

DatasetReader::DatasetReader(const fs::path& folder) : folder_(folder) {
  if (!fs::is_directory(folder)) {
    throw DatasetError(folder.string() + ": not a folder (a gvs dataset is a folder holding camera.json, frames.csv, frames/)");
  }
  camera_ = read_camera_json(folder / "camera.json");
  frames_ = read_frames_csv(folder / "frames.csv");
  if (fs::exists(folder / "truth.csv")) truth_ = read_truth_csv(folder / "truth.csv");
}

cv::Mat DatasetReader::load_gray(std::size_t i) const {
  const FrameRecord& r = frames_.at(i);
  const fs::path file = folder_ / r.file;
  if (!fs::is_regular_file(file)) {
    fail(file, "missing (named by frames.csv, index " + std::to_string(r.index) + ")");
  }
  PngRead png = read_png(file.string(), PngPixels::unchanged);
  if (png.pixels.empty()) {
    fail(file, "unreadable or truncated image (index " + std::to_string(r.index) + "): " + png.error);
  }
  const cv::Mat raw = png.pixels;
  cv::Mat gray;
  if (raw.channels() == 1) {
    gray = raw;
  } else if (raw.channels() == 3) {
    cv::cvtColor(raw, gray, cv::COLOR_BGR2GRAY);
  } else if (raw.channels() == 4) {
    cv::cvtColor(raw, gray, cv::COLOR_BGRA2GRAY);
  } else {
    fail(file, "has " + std::to_string(raw.channels()) + " channels; expected gray or colour");
  }
  if (gray.depth() == CV_16U) {
    gray.convertTo(gray, CV_8U, 1.0 / 257.0);
  } else if (gray.depth() != CV_8U) {
    fail(file, "has an unsupported pixel depth; expected 8- or 16-bit");
  }
  const core::CameraGeometry& g = camera_.geometry;
  if (gray.cols != g.width_px || gray.rows != g.height_px) {
    fail(file, "is " + std::to_string(gray.cols) + "x" + std::to_string(gray.rows) + " px but camera.json says " +
                   std::to_string(g.width_px) + "x" + std::to_string(g.height_px));
  }
  return gray;
}

core::ExposurePlan parse_pulses(const std::string& text, double exposure_us) {
  core::ExposurePlan plan;
  plan.exposure_us = exposure_us;
  plan.pulse_count = 0;
  std::string_view rest(text);
  while (!rest.empty() && (rest.back() == ' ' || rest.back() == '\r')) rest.remove_suffix(1);
  if (rest.empty()) return plan;
  while (true) {
    const std::size_t bar = rest.find('|');
    const std::string_view item = rest.substr(0, bar);
    const std::size_t colon = item.find(':');
    if (colon == std::string_view::npos) {
      throw std::invalid_argument("'" + std::string(item) + "' is not start_us:duration_us");
    }
    core::LightPulse p;
    if (!parse_double(item.substr(0, colon), p.start_us) || !parse_double(item.substr(colon + 1), p.duration_us)) {
      throw std::invalid_argument("'" + std::string(item) + "' is not two numbers start_us:duration_us");
    }
    if (p.start_us < 0.0 || p.duration_us <= 0.0) {
      throw std::invalid_argument("'" + std::string(item) + "' needs start_us >= 0 and duration_us > 0");
    }
    if (plan.pulse_count == core::ExposurePlan::kMaxPulses) {
      throw std::invalid_argument("more than " + std::to_string(core::ExposurePlan::kMaxPulses) + " pulses");
    }
    if (plan.pulse_count > 0) {
      const core::LightPulse& prev = plan.pulses[plan.pulse_count - 1];
      if (p.start_us < prev.start_us + prev.duration_us) {
        throw std::invalid_argument("pulses overlap or are out of order at '" + std::string(item) + "'");
      }
    }
    plan.pulses[plan.pulse_count++] = p;
    if (bar == std::string_view::npos) break;
    rest.remove_prefix(bar + 1);
  }
  return plan;
}

}  // namespace gvs::drivers
