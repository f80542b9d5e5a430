// camera.json's optional key "lasers": the geometry of the head's laser
// dots (core::LaserGeometry; docs/simulator.md, "Laser dots"). Datasets
// without it read as before (no lasers).
#pragma once

#include <filesystem>

#include <nlohmann/json.hpp>

#include "gvs/core/laser_geometry.hpp"

namespace gvs::drivers::detail {

nlohmann::ordered_json laser_geometry_json(const core::LaserGeometry& lasers);
/// Throws DatasetError naming `file` and the key that is wrong.
core::LaserGeometry laser_geometry_from_json(const nlohmann::json& j, const std::filesystem::path& file);

}  // namespace gvs::drivers::detail
