// The periodic asphalt and its tile (gvsd's live simulated camera): the
// texture repeats exactly at its period, keeps the non-periodic texture's
// statistics, and the tile reproduces the texture it was rendered from.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "asphalt.hpp"
#include "texture_tile.hpp"

namespace gvs::drivers::sim {
namespace {

RasterGrid world_grid(double spacing_mm, int rows, int cols, double u0 = 0.0, double v0 = 0.0) {
  RasterGrid g;
  g.spacing_mm = spacing_mm;
  g.spacing_u_mm = spacing_mm;
  g.rows = rows;
  g.cols = cols;
  g.u0 = u0;
  g.v0 = v0;
  return g;
}

std::vector<float> render(const AsphaltTexture& t, const RasterGrid& g) {
  std::vector<float> out(static_cast<std::size_t>(g.rows) * static_cast<std::size_t>(g.cols));
  t.render_rows(g, 0, g.rows, out.data());
  return out;
}

std::vector<float> render(const TextureTile& t, const RasterGrid& g) {
  std::vector<float> out(static_cast<std::size_t>(g.rows) * static_cast<std::size_t>(g.cols));
  t.render_rows(g, 0, g.rows, out.data());
  return out;
}

double max_abs_diff(const std::vector<float>& a, const std::vector<float>& b) {
  double d = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) d = std::max(d, static_cast<double>(std::abs(a[i] - b[i])));
  return d;
}

void mean_std(const std::vector<float>& v, double& mean, double& sd) {
  double s = 0.0, s2 = 0.0;
  for (const float f : v) {
    const auto x = static_cast<double>(f);
    s += x;
    s2 += x * x;
  }
  mean = s / static_cast<double>(v.size());
  sd = std::sqrt(s2 / static_cast<double>(v.size()) - mean * mean);
}

TEST(SimTextureTile, PeriodicTextureRepeatsAtItsPeriod) {
  const AsphaltTexture t(5, 72.0);
  // 0.08 mm spacing: 72 mm = 900 samples, shifted by one period in x, in y and in both.
  const auto base = render(t, world_grid(0.08, 60, 300, 100.0, 40.0));
  EXPECT_LT(max_abs_diff(base, render(t, world_grid(0.08, 60, 300, 100.0 + 900.0, 40.0))), 1e-3);
  EXPECT_LT(max_abs_diff(base, render(t, world_grid(0.08, 60, 300, 100.0, 40.0 - 900.0))), 1e-3);
  EXPECT_LT(max_abs_diff(base, render(t, world_grid(0.08, 60, 300, 100.0 - 1800.0, 40.0 + 900.0))), 1e-3);
  // ... and not at a shift that is not a period.
  EXPECT_GT(max_abs_diff(base, render(t, world_grid(0.08, 60, 300, 100.0 + 450.0, 40.0))), 0.1);
  EXPECT_THROW(AsphaltTexture(5, 50.0), std::invalid_argument);
}

TEST(SimTextureTile, PeriodicTextureKeepsTheStatistics) {
  const RasterGrid g = world_grid(0.05, 800, 800);  // 40 x 40 mm
  double m0 = 0.0, s0 = 0.0, m1 = 0.0, s1 = 0.0;
  mean_std(render(AsphaltTexture(9), g), m0, s0);
  mean_std(render(AsphaltTexture(9, 108.0), g), m1, s1);
  EXPECT_NEAR(m1, m0, 0.05 * m0);
  EXPECT_NEAR(s1, s0, 0.08 * s0);
}

TEST(SimTextureTile, TileReproducesItsTexture) {
  const AsphaltTexture t(3, 108.0);
  const TextureTile tile(t, 0.05);
  // 108 mm / 0.05 mm = 2160 -> the nearest power of two, 2048.
  EXPECT_EQ(tile.size(), 2048);
  EXPECT_NEAR(tile.spacing_mm(), 108.0 / 2048.0, 1e-12);
  // On the tile's own samples (any whole number of periods away) it is the texture.
  const double h = tile.spacing_mm();
  for (const double u0 : {0.0, 300.0, 300.0 + 2048.0, 300.0 - 3.0 * 2048.0}) {
    const RasterGrid g = world_grid(h, 40, 500, u0, 77.0);
    RasterGrid at_home = g;
    at_home.u0 = 300.0;
    EXPECT_LT(max_abs_diff(render(tile, g), render(t, u0 == 0.0 ? g : at_home)), 1e-4) << "u0 " << u0;
  }
  // Between samples, on a rotated raster: the same texture, slightly smoothed
  // by the interpolation (mean equal, contrast within 10 %).
  RasterGrid rotated = world_grid(0.05, 400, 400, -1234.0, 567.0);
  rotated.ux = std::cos(0.3);
  rotated.uy = std::sin(0.3);
  double m0 = 0.0, s0 = 0.0, m1 = 0.0, s1 = 0.0;
  mean_std(render(t, rotated), m0, s0);
  mean_std(render(tile, rotated), m1, s1);
  EXPECT_NEAR(m1, m0, 0.01 * m0);
  EXPECT_NEAR(s1, s0, 0.10 * s0);
  EXPECT_LT(s1, s0);
}

TEST(SimTextureTile, PeriodFitsTheViewAndAPowerOfTwo) {
  // 512 x 384 px at 0.1 mm/px (51.2 x 38.4 mm), raster at 0.05 mm.
  const double p = TextureTile::period_for_view(51.2, 38.4, 0.05);
  EXPECT_GE(p, 1.5 * 51.2);
  EXPECT_LE(p, 3.0 * 51.2 + 36.0);
  EXPECT_NEAR(std::fmod(p, 36.0), 0.0, 1e-9);
  const double n = p / 0.05;
  EXPECT_LT(std::abs(std::log2(n) - std::round(std::log2(n))), 0.1);
}

}  // namespace
}  // namespace gvs::drivers::sim
