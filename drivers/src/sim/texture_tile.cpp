// TextureTile: one period of a periodic asphalt texture, bilinearly resampled.
#include "texture_tile.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include <opencv2/core/utility.hpp>

namespace gvs::drivers::sim {

double TextureTile::period_for_view(double width_mm, double height_mm, double spacing_mm) {
  const double step = AsphaltTexture::kPeriodStepMm;
  const double k_min = std::max(1.0, std::ceil(1.5 * std::max(width_mm, height_mm) / step));
  double best = k_min * step;
  double best_misfit = 1e9;
  for (double k = k_min; k <= 2.0 * k_min; k += 1.0) {
    const double octaves = std::log2(k * step / spacing_mm);
    const double misfit = std::abs(octaves - std::round(octaves));
    if (misfit < best_misfit - 1e-9) {
      best_misfit = misfit;
      best = k * step;
    }
  }
  return best;
}

int TextureTile::side_for(double period_mm, double spacing_mm) {
  const double octaves = std::round(std::log2(std::max(1.0, period_mm / spacing_mm)));
  return 1 << static_cast<int>(std::min(octaves, 20.0));
}

TextureTile::TextureTile(const AsphaltTexture& texture, double spacing_mm)
    : TextureTile(texture, spacing_mm, 0.0) {}

TextureTile::TextureTile(const AsphaltTexture& texture, double spacing_mm, double psf_sigma_mm, int keep_every)
    : period_mm_(texture.period_mm()) {
  if (keep_every != 1 && keep_every != 2)
    throw std::invalid_argument("simulator: texture tile keeps every 1st or 2nd sample");
  if (!(period_mm_ > 0.0)) throw std::invalid_argument("simulator: a texture tile needs a periodic texture");
  if (!(spacing_mm > 0.0)) throw std::invalid_argument("simulator: texture tile spacing must be > 0");
  n_ = side_for(period_mm_, spacing_mm);
  if (n_ > 4096)
    throw std::invalid_argument("simulator: texture tile would need " + std::to_string(n_) +
                                " samples a side (period " + std::to_string(period_mm_) + " mm at " +
                                std::to_string(spacing_mm) + " mm); at most 4096");
  spacing_mm_ = period_mm_ / n_;
  samples_.resize(static_cast<std::size_t>(n_) * static_cast<std::size_t>(n_));
  RasterGrid grid;  // world-aligned, origin at the world origin
  grid.spacing_mm = spacing_mm_;
  grid.spacing_u_mm = spacing_mm_;
  grid.rows = n_;
  grid.cols = n_;
  const int strips = std::max(1, n_ / 64);
  cv::parallel_for_(cv::Range(0, strips), [&](const cv::Range& range) {
    for (int s = range.start; s < range.end; ++s) {
      const int r0 = n_ * s / strips;
      const int r1 = n_ * (s + 1) / strips;
      texture.render_rows(grid, r0, r1, samples_.data() + static_cast<std::ptrdiff_t>(r0) * n_);
    }
  });
  if (psf_sigma_mm > 0.0) {
    blur(psf_sigma_mm / spacing_mm_);
    psf_sigma_mm_ = psf_sigma_mm;
  }
  if (keep_every == 2 && n_ >= 2) keep_every_other();
}

void TextureTile::keep_every_other() {
  const int half = n_ / 2;
  for (int r = 0; r < half; ++r) {
    const float* src = samples_.data() + static_cast<std::ptrdiff_t>(2 * r) * n_;
    float* dst = samples_.data() + static_cast<std::ptrdiff_t>(r) * half;
    for (int c = 0; c < half; ++c) dst[c] = src[2 * c];
  }
  n_ = half;
  spacing_mm_ *= 2.0;
  samples_.resize(static_cast<std::size_t>(n_) * static_cast<std::size_t>(n_));
  samples_.shrink_to_fit();
}

void TextureTile::blur(double sigma_samples) {
  // Separable Gaussian, +-3 sigma, wrapped around the period (the tile is periodic).
  const int radius = std::max(1, static_cast<int>(std::ceil(3.0 * sigma_samples)));
  std::vector<float> taps(static_cast<std::size_t>(2 * radius + 1));
  double sum = 0.0;
  for (int k = -radius; k <= radius; ++k) sum += std::exp(-0.5 * k * k / (sigma_samples * sigma_samples));
  for (int k = -radius; k <= radius; ++k)
    taps[static_cast<std::size_t>(k + radius)] =
        static_cast<float>(std::exp(-0.5 * k * k / (sigma_samples * sigma_samples)) / sum);
  const int mask = n_ - 1;
  std::vector<float> across(samples_.size());
  // Along the rows (columns wrap), into `across`; then along the columns back into samples_.
  cv::parallel_for_(cv::Range(0, n_), [&](const cv::Range& range) {
    for (int r = range.start; r < range.end; ++r) {
      const float* src = samples_.data() + static_cast<std::ptrdiff_t>(r) * n_;
      float* dst = across.data() + static_cast<std::ptrdiff_t>(r) * n_;
      for (int c = 0; c < n_; ++c) {
        float acc = 0.0f;
        for (int k = -radius; k <= radius; ++k) acc += taps[static_cast<std::size_t>(k + radius)] * src[(c + k) & mask];
        dst[c] = acc;
      }
    }
  });
  cv::parallel_for_(cv::Range(0, n_), [&](const cv::Range& range) {
    for (int r = range.start; r < range.end; ++r) {
      float* dst = samples_.data() + static_cast<std::ptrdiff_t>(r) * n_;
      std::fill(dst, dst + n_, 0.0f);
      for (int k = -radius; k <= radius; ++k) {
        const float w = taps[static_cast<std::size_t>(k + radius)];
        const float* src = across.data() + static_cast<std::ptrdiff_t>((r + k) & mask) * n_;
        for (int c = 0; c < n_; ++c) dst[c] += w * src[c];
      }
    }
  });
}

void TextureTile::render_rows(const RasterGrid& grid, int row_begin, int row_end, float* out) const {
  // Tile coordinates: column (x) and row (y) in samples. The world-aligned
  // tile grid above has x along its columns and y along its rows.
  const auto mask = n_ - 1;
  double x0 = 0.0, y0 = 0.0, x1 = 0.0, y1 = 0.0;
  grid.to_world(0.0, 0.0, x0, y0);
  grid.to_world(1.0, 0.0, x1, y1);
  const double step_x = (x1 - x0) / spacing_mm_;
  const double step_y = (y1 - y0) / spacing_mm_;
  const float* tile = samples_.data();
  for (int r = row_begin; r < row_end; ++r) {
    float* row = out + static_cast<std::ptrdiff_t>(r - row_begin) * grid.cols;
    grid.to_world(0.0, r, x0, y0);
    // Reduce the row's start into [0, n) once, then lift it by whole periods
    // so that every sample of the row stays positive: truncation is floor.
    const double n = static_cast<double>(n_);
    const double lift_x = n * std::ceil(std::abs(step_x) * grid.cols / n + 1.0);
    const double lift_y = n * std::ceil(std::abs(step_y) * grid.cols / n + 1.0);
    const double tx0 = x0 / spacing_mm_ - n * std::floor(x0 / spacing_mm_ / n) + lift_x;
    const double ty0 = y0 / spacing_mm_ - n * std::floor(y0 / spacing_mm_ / n) + lift_y;
    for (int c = 0; c < grid.cols; ++c) {
      const double tx = tx0 + c * step_x;
      const double ty = ty0 + c * step_y;
      const int fx = static_cast<int>(tx);
      const int fy = static_cast<int>(ty);
      const auto wx = static_cast<float>(tx - fx);
      const auto wy = static_cast<float>(ty - fy);
      const int ix = fx & mask;
      const int iy = fy & mask;
      const int ix1 = (ix + 1) & mask;
      const float* r0 = tile + static_cast<std::ptrdiff_t>(iy) * n_;
      const float* r1 = tile + static_cast<std::ptrdiff_t>((iy + 1) & mask) * n_;
      const float a = r0[ix] + wx * (r0[ix1] - r0[ix]);
      const float b = r1[ix] + wx * (r1[ix1] - r1[ix]);
      row[c] = a + wy * (b - a);
    }
  }
}

}  // namespace gvs::drivers::sim
