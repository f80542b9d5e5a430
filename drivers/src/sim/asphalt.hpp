// Procedural asphalt reflectance in world coordinates, rendered by stamping
// stones into a raster (docs/simulator.md, "Texture").
#pragma once

#include <cstdint>
#include <vector>

namespace gvs::drivers::sim {

/// A raster whose axes may be rotated against the world. Sample (i, j) lies at
/// the world point (U0 + j) hu u + (V0 + i) hv v, with u = (ux, uy) a unit
/// vector, v = (-uy, ux), hu = spacing_u_mm (along rows), hv = spacing_mm
/// (across), and U0, V0 integers (so rasters with the same orientation and
/// spacing share sample positions).
struct RasterGrid {
  double u0 = 0.0;  ///< U0 (integer valued)
  double v0 = 0.0;  ///< V0 (integer valued)
  double ux = 1.0;
  double uy = 0.0;
  double spacing_mm = 0.05;    ///< hv: between rows
  double spacing_u_mm = 0.05;  ///< hu: along a row (the motion axis)
  int rows = 0;
  int cols = 0;

  /// Raster coordinates (col j, row i) of a world point in mm.
  void to_raster(double x_mm, double y_mm, double& j, double& i) const {
    j = (x_mm * ux + y_mm * uy) / spacing_u_mm - u0;
    i = (-x_mm * uy + y_mm * ux) / spacing_mm - v0;
  }
  /// World point (mm) of raster coordinates (j, i).
  void to_world(double j, double i, double& x_mm, double& y_mm) const {
    const double a = (u0 + j) * spacing_u_mm;
    const double b = (v0 + i) * spacing_mm;
    x_mm = a * ux - b * uy;
    y_mm = a * uy + b * ux;
  }
};

/// The asphalt of one seed: reflectance in [0, 1] at every world point.
class AsphaltTexture {
 public:
  explicit AsphaltTexture(std::uint64_t seed);
  /// A texture that repeats every `period_mm` along x and y (a multiple of
  /// kPeriodStepMm): every hashed lattice index wraps, and the feature cells
  /// are resized so that a whole number of them fits the period. Same
  /// statistics, different stones from the non-periodic texture of the seed.
  AsphaltTexture(std::uint64_t seed, double period_mm);

  /// Renders raster rows [row_begin, row_end) into `out` (row-major, grid.cols
  /// floats per row, first row = row_begin). Thread-safe (const).
  void render_rows(const RasterGrid& grid, int row_begin, int row_end, float* out) const;

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
