// A seamless photograph of asphalt laid over the world plane in randomised,
// blended tiles, so that it never repeats exactly (docs/simulator.md,
// "Photographed ground").
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <opencv2/core/mat.hpp>

#include "ground.hpp"

namespace gvs::drivers::sim {

class PhotoGround final : public Ground {
 public:
  /// Loads `file` (8-bit grey; colour is converted), square, at least 16 px,
  /// and seamless (it wraps around at its edges). Throws std::invalid_argument
  /// naming the file when it is missing, unreadable or not square, or when
  /// `mm_per_pixel` is outside [0.01, 5].
  PhotoGround(const std::string& file, double mm_per_pixel, std::uint64_t seed);
  /// The same from an 8-bit grey image in memory; `name` stands for the file in messages.
  PhotoGround(const cv::Mat& grey, double mm_per_pixel, std::uint64_t seed, const std::string& name);

  void render_rows(const RasterGrid& grid, int row_begin, int row_end, float* out) const override;

  /// Side of one tile: the photo's side in mm.
  [[nodiscard]] double period_mm() const { return period_mm_; }
  /// Half-width of the cross-fade band on each side of a tile border.
  [[nodiscard]] double blend_half_width_mm() const { return blend_half_width_mm_; }
  /// Mean reflectance of the mapped photo (kProceduralMeanReflectance).
  [[nodiscard]] double mean_reflectance() const { return mean_; }

  /// Mean reflectance of the procedural asphalt (AsphaltTexture), to which the
  /// photo's mean grey is scaled so both give the same brightness under the
  /// same light (checked by the tests against the procedural texture).
  static constexpr double kProceduralMeanReflectance = 0.238;
  /// Cross-fade band: half-width as a fraction of the tile side.
  static constexpr double kBlendHalfWidthFraction = 1.0 / 16.0;

 private:
  /// Where one tile samples the photo: integer offset and one of the 8 square
  /// symmetries (bit 0: mirror u, bit 1: mirror v, bit 2: swap u and v).
  struct TileMap {
    double offset_u = 0.0;
    double offset_v = 0.0;
    int symmetry = 0;
  };
  [[nodiscard]] TileMap tile_map(std::int64_t tx, std::int64_t ty) const;
  /// Bilinear, wrapped sample at photo coordinates (u, v) in pixels (pixel k spans [k, k + 1)).
  [[nodiscard]] float sample(double u, double v) const;
  /// Reflectance tile (tx, ty) gives at world point (x, y), also outside the tile.
  [[nodiscard]] float tile_value(const TileMap& m, std::int64_t tx, std::int64_t ty, double x_mm,
                                 double y_mm) const;

  int n_ = 0;
  double mm_per_pixel_ = 0.0;
  double period_mm_ = 0.0;
  double blend_half_width_mm_ = 0.0;
  std::uint64_t seed_ = 0;
  double mean_ = 0.0;
  std::vector<float> texels_;  ///< n x n reflectance, row-major (v = row, u = column)
};

}  // namespace gvs::drivers::sim
