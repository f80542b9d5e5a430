// The ground under the camera as the exposure renderer sees it: reflectance
// on a (possibly rotated) raster in world coordinates. Procedural asphalt,
// its periodic tile and a photograph all implement it (docs/simulator.md).
#pragma once

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

/// Reflectance in [0, 1] at every world point of the plane.
class Ground {
 public:
  virtual ~Ground() = default;
  /// Renders raster rows [row_begin, row_end) into `out` (row-major, grid.cols
  /// floats per row, first row = row_begin). Thread-safe (const): strips of
  /// one raster are rendered in parallel.
  virtual void render_rows(const RasterGrid& grid, int row_begin, int row_end, float* out) const = 0;

 protected:
  Ground() = default;
  Ground(const Ground&) = default;
  Ground& operator=(const Ground&) = default;
  Ground(Ground&&) = default;
  Ground& operator=(Ground&&) = default;
};

}  // namespace gvs::drivers::sim
