#include "laser_json.hpp"

#include <cmath>
#include <fstream>
#include <string>

#include "gvs/drivers/dataset.hpp"

namespace gvs::drivers::detail {

nlohmann::ordered_json laser_geometry_json(const core::LaserGeometry& lasers) {
  nlohmann::ordered_json j;
  j["spot_sigma_mm"] = lasers.spot_sigma_mm;
  j["min_height_mm"] = lasers.min_height_mm;
  j["max_height_mm"] = lasers.max_height_mm;
  nlohmann::ordered_json beams = nlohmann::ordered_json::array();
  for (std::size_t k = 0; k < lasers.count; ++k) {
    const core::LaserBeam& b = lasers.beams[k];
    nlohmann::ordered_json o;
    o["x_mm"] = b.x_mm;
    o["y_mm"] = b.y_mm;
    o["z_mm"] = b.z_mm;
    o["azimuth_deg"] = b.azimuth_deg;
    o["tilt_deg"] = b.tilt_deg;
    beams.push_back(o);
  }
  j["beams"] = beams;
  return j;
}

core::LaserGeometry laser_geometry_from_json(const nlohmann::json& j, const std::filesystem::path& file) {
  auto fail = [&](const std::string& what) -> void {
    throw DatasetError(file.string() + ": key 'lasers': " + what + " (docs/simulator.md, \"Laser dots\")");
  };
  if (!j.is_object()) fail("must be an object with 'beams'");
  auto number = [&](const nlohmann::json& o, const char* key, double fallback, bool required) -> double {
    if (!o.contains(key)) {
      if (required) fail(std::string("a beam lacks '") + key + "'");
      return fallback;
    }
    if (!o.at(key).is_number() || !std::isfinite(o.at(key).get<double>()))
      fail(std::string("'") + key + "' must be a finite number");
    return o.at(key).get<double>();
  };
  core::LaserGeometry g;
  g.spot_sigma_mm = number(j, "spot_sigma_mm", g.spot_sigma_mm, false);
  g.min_height_mm = number(j, "min_height_mm", g.min_height_mm, false);
  g.max_height_mm = number(j, "max_height_mm", g.max_height_mm, false);
  if (!(g.spot_sigma_mm > 0.0)) fail("'spot_sigma_mm' must be positive");
  if (!(g.min_height_mm > 0.0 && g.max_height_mm > g.min_height_mm))
    fail("'min_height_mm' must be positive and below 'max_height_mm'");
  if (!j.contains("beams") || !j.at("beams").is_array()) fail("'beams' must be an array");
  const nlohmann::json& beams = j.at("beams");
  if (beams.size() > core::LaserGeometry::kMaxBeams) fail("at most " + std::to_string(core::LaserGeometry::kMaxBeams) + " beams");
  g.count = beams.size();
  for (std::size_t k = 0; k < g.count; ++k) {
    const nlohmann::json& o = beams.at(k);
    if (!o.is_object()) fail("each beam must be an object");
    core::LaserBeam& b = g.beams[k];
    b.x_mm = number(o, "x_mm", 0.0, true);
    b.y_mm = number(o, "y_mm", 0.0, true);
    b.z_mm = number(o, "z_mm", 0.0, true);
    b.azimuth_deg = number(o, "azimuth_deg", 0.0, true);
    b.tilt_deg = number(o, "tilt_deg", 0.0, true);
    if (!(b.tilt_deg > 0.0 && b.tilt_deg < 80.0)) fail("'tilt_deg' must be in (0, 80) degrees from straight down");
  }
  return g;
}

}  // namespace gvs::drivers::detail

namespace gvs::drivers {
std::string laser_geometry_json_text(const core::LaserGeometry& lasers) {
  return detail::laser_geometry_json(lasers).dump(2);
}

core::LaserGeometry load_laser_geometry(const std::filesystem::path& file) {
  std::ifstream in(file);
  if (!in) throw DatasetError(file.string() + ": cannot read the laser geometry (write it with `gvs calibrate height --out`)");
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception& e) {
    throw DatasetError(file.string() + ": not JSON (" + e.what() + ")");
  }
  // A camera.json carries the geometry under "lasers"; calibrate's file is the object itself.
  const nlohmann::json& lasers = j.is_object() && j.contains("lasers") ? j.at("lasers") : j;
  core::LaserGeometry g = detail::laser_geometry_from_json(lasers, file);
  if (!g.enabled()) throw DatasetError(file.string() + ": key 'lasers': 'beams' is empty");
  return g;
}
}  // namespace gvs::drivers
