// Which ground the simulator renders: the procedural asphalt or a seamless
// photograph laid over the plane (docs/simulator.md, "Photographed ground").
#pragma once

#include <string>

namespace gvs::drivers::sim {

struct GroundSpec {
  enum class Kind { procedural, photo };
  static constexpr double kDefaultPhotoMmPerPixel = 0.2;  ///< real asphalt photos: about 0.1-0.3
  static constexpr double kMinPhotoMmPerPixel = 0.01;
  static constexpr double kMaxPhotoMmPerPixel = 5.0;

  Kind kind = Kind::procedural;
  std::string photo_file;  ///< photo only: a seamless, square 8-bit image
  double photo_mm_per_pixel = kDefaultPhotoMmPerPixel;
};

/// Parses "procedural" or "photo:FILE[:MM_PER_PIXEL]" (the text after the
/// last ':' is the scale; a FILE that contains ':' therefore needs the scale).
/// Throws std::invalid_argument naming the text, the file and the syntax.
GroundSpec parse_ground(const std::string& text);

/// The canonical text of a ground: "procedural" or "photo:FILE:MM_PER_PIXEL"
/// (what datasets record).
std::string ground_text(const GroundSpec& ground);

}  // namespace gvs::drivers::sim
