// A periodic asphalt texture rendered once into a square tile and resampled
// for every frame: the live simulated camera's cheap texture (docs/simulator.md,
// "Live source").
#pragma once

#include <vector>

#include "asphalt.hpp"

namespace gvs::drivers::sim {

class TextureTile final : public Ground {
 public:
  /// Renders `texture` (which must be periodic) over one period at about
  /// `spacing_mm`: N x N samples, N the power of two nearest to
  /// period / spacing (<= 4096), so wrapping is a bit mask.
  TextureTile(const AsphaltTexture& texture, double spacing_mm);
  /// The same, then blurred once with an isotropic Gaussian of `psf_sigma_mm`
  /// (wrapped around the period): the pixel/optics PSF baked into the tile,
  /// for the live fast render (docs/simulator.md, "Live source"). 0: none.
  /// `keep_every` 2 then keeps every other sample in both axes (a tile at
  /// twice the spacing, a quarter of the memory; the blur before it is the
  /// anti-aliasing filter).
  TextureTile(const AsphaltTexture& texture, double spacing_mm, double psf_sigma_mm, int keep_every = 1);

  /// The same contract as AsphaltTexture::render_rows: raster rows
  /// [row_begin, row_end) of `grid` into `out`, by bilinear interpolation of
  /// the tile, wrapped around its period.
  void render_rows(const RasterGrid& grid, int row_begin, int row_end, float* out) const override;

  [[nodiscard]] int size() const { return n_; }
  [[nodiscard]] double spacing_mm() const { return spacing_mm_; }
  [[nodiscard]] double period_mm() const { return period_mm_; }
  /// Gaussian blur baked into the samples (0: none).
  [[nodiscard]] double psf_sigma_mm() const { return psf_sigma_mm_; }

  /// Period for a view `width_mm` x `height_mm` sampled at `spacing_mm`: a
  /// multiple of 36 mm, at least 1.5 times the view's longest side (no frame
  /// sees a repeat: P_min, rounded up to 36 mm) and at most 2 P_min, chosen so that period / spacing is
  /// nearest to a power of two (the tile's spacing then stays within a few
  /// per cent of the one asked for).
  static double period_for_view(double width_mm, double height_mm, double spacing_mm);
  /// N for a period and a spacing: the power of two nearest to period / spacing.
  static int side_for(double period_mm, double spacing_mm);

 private:
  int n_ = 0;
  double period_mm_ = 0.0;
  double spacing_mm_ = 0.0;
  double psf_sigma_mm_ = 0.0;
  std::vector<float> samples_;

  void blur(double sigma_samples);
  void keep_every_other();
};

}  // namespace gvs::drivers::sim
