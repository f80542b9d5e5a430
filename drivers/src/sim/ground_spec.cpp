// Parsing the ground of a run: `procedural` or `photo:FILE[:MM_PER_PIXEL]`.
#include "gvs/drivers/sim/ground_spec.hpp"

#include <cstdio>
#include <cstdlib>
#include <stdexcept>

namespace gvs::drivers::sim {
namespace {

constexpr const char* kSyntax = "use procedural or photo:FILE[:MM_PER_PIXEL], e.g. photo:asphalt.png:0.2";

}  // namespace

GroundSpec parse_ground(const std::string& text) {
  GroundSpec g;
  if (text == "procedural") return g;
  const std::string prefix = "photo:";
  if (text.rfind(prefix, 0) != 0)
    throw std::invalid_argument("simulator: ground '" + text + "' is unknown; " + kSyntax);
  std::string file = text.substr(prefix.size());
  const auto colon = file.rfind(':');
  if (colon != std::string::npos) {
    const std::string scale = file.substr(colon + 1);
    file.resize(colon);
    char* end = nullptr;
    const double mm = std::strtod(scale.c_str(), &end);
    if (scale.empty() || end != scale.c_str() + scale.size() || !(mm >= GroundSpec::kMinPhotoMmPerPixel) ||
        !(mm <= GroundSpec::kMaxPhotoMmPerPixel))
      throw std::invalid_argument("simulator: ground '" + text + "': the scale '" + scale + "' of photo '" + file +
                                  "' must be millimetres per photo pixel in [0.01, 5] (real asphalt photos: "
                                  "about 0.1-0.3; leave it out for 0.2)");
    g.photo_mm_per_pixel = mm;
  }
  if (file.empty()) throw std::invalid_argument("simulator: ground '" + text + "' names no photo file; " + kSyntax);
  g.kind = GroundSpec::Kind::photo;
  g.photo_file = file;
  return g;
}

std::string ground_text(const GroundSpec& ground) {
  if (ground.kind == GroundSpec::Kind::procedural) return "procedural";
  char scale[32];
  std::snprintf(scale, sizeof scale, "%.9g", ground.photo_mm_per_pixel);
  return "photo:" + ground.photo_file + ":" + scale;
}

}  // namespace gvs::drivers::sim
