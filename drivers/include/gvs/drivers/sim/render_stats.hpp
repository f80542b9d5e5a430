// What rendering the last simulated frame cost (benchmarks, docs/simulator.md).
#pragma once

#include <cstddef>

namespace gvs::drivers::sim {

struct RenderStats {
  int raster_rows = 0;        ///< motion-aligned texture raster (spacing s/2; s for the live fast render)
  int raster_cols = 0;
  std::size_t knots = 0;      ///< path knots over all light intervals
  double texture_ms = 0.0;    ///< asphalt raster
  double psf_ms = 0.0;        ///< PSF blur + prefix sums
  double integrate_ms = 0.0;  ///< per-pixel path integrals
  double sensor_ms = 0.0;     ///< light falloff, noise, quantisation
  bool box_filtered = false;  ///< live fast render: path integrals as box filters (the view only translated)
};

}  // namespace gvs::drivers::sim
