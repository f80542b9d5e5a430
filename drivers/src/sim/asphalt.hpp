// Procedural asphalt reflectance in world coordinates, rendered by stamping
// stones into a raster (docs/simulator.md, "Texture").
#pragma once

#include <cstdint>
#include <vector>

#include "ground.hpp"

namespace gvs::drivers::sim {

/// The asphalt of one seed: reflectance in [0, 1] at every world point.
class AsphaltTexture final : public Ground {
 public:
  explicit AsphaltTexture(std::uint64_t seed);
  /// A texture that repeats every `period_mm` along x and y (a multiple of
  /// kPeriodStepMm): every hashed lattice index wraps, and the feature cells
  /// are resized so that a whole number of them fits the period. Same
  /// statistics, different stones from the non-periodic texture of the seed.
  AsphaltTexture(std::uint64_t seed, double period_mm);

  /// Renders raster rows [row_begin, row_end) into `out` (row-major, grid.cols
  /// floats per row, first row = row_begin). Thread-safe (const).
  void render_rows(const RasterGrid& grid, int row_begin, int row_end, float* out) const override;

  /// Kinds of stamped features, drawn in this order, each only into pixels
  /// still uncovered; then binder grain and stone speckle (value noise).
  enum class Kind { stone, pore, sand };
  struct FeatureClass {
    Kind kind;
    double r_min_mm;
    double r_max_mm;
    double cover;      ///< nominal area fraction (before masking by earlier classes)
    double occupancy;  ///< probability that a cell holds a feature
    double cell_mm;    ///< derived from cover and occupancy
  };
  [[nodiscard]] const std::vector<FeatureClass>& classes() const { return classes_; }

  static constexpr float kBitumen = 0.10f;   ///< reflectance of bare binder
  static constexpr double kFineLatticeMm = 0.12;   ///< fine grain lattice
  static constexpr double kMediumLatticeMm = 0.45; ///< medium mottle lattice
  static constexpr double kWearLatticeMm = 12.0;   ///< slow wear / dust variation of the stones
  /// Periods must be multiples of this (the lattices above all divide it).
  static constexpr double kPeriodStepMm = 36.0;
  [[nodiscard]] double period_mm() const { return period_mm_; }

 private:
  void stamp_class(std::size_t class_index, const RasterGrid& grid, int row_begin, int row_end,
                   float* out) const;
  void add_grain(const RasterGrid& grid, int row_begin, int row_end, float* out) const;
  void add_grain_periodic(const RasterGrid& grid, int row_begin, int row_end, float* out) const;
  /// Lattice index as hashed: wrapped to [0, n) for a periodic texture (n =
  /// period / lattice spacing), unchanged otherwise.
  [[nodiscard]] std::int64_t wrap(std::int64_t index, double lattice_mm) const;

  std::uint64_t seed_;
  double period_mm_ = 0.0;  ///< 0: never repeats
  std::vector<FeatureClass> classes_;
};

}  // namespace gvs::drivers::sim
