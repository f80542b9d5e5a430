// PhotoGround: the world is cut into square tiles one photo wide. Each tile
// shows the photo shifted by its own hashed offset and turned by one of the 8
// square symmetries, so no two tiles match; near a tile border the two (at a
// corner four) tiles are cross-faded with weights normalised to keep the
// texture's variance, so no straight seam shows as an edge.
#include "photo_ground.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <utility>

#include "gvs/drivers/png_file.hpp"
#include "gvs/drivers/sim/ground_spec.hpp"
#include "hash.hpp"

namespace gvs::drivers::sim {
namespace {

constexpr std::uint64_t kTileSalt = 0x9407;

cv::Mat load_grey(const std::string& file) {
  std::error_code ec;
  const bool exists = std::filesystem::is_regular_file(file, ec);
  const cv::Mat grey = exists ? read_png(file, PngPixels::grey).pixels : cv::Mat();
  if (grey.empty())
    throw std::invalid_argument("simulator: ground photo '" + file +
                                "' is missing or not a readable image; give a seamless square 8-bit grey PNG, "
                                "e.g. ../shared/testdata/real-asphalt/ph_asphalt_04_1024.png");
  return grey;
}

/// Smooth step on [0, 1] (zero slope at both ends, so the weights have no kink at the band's edge).
inline double smooth(double t) { return t * t * (3.0 - 2.0 * t); }

/// Weight of the sample's own tile along one axis, and which neighbour (-1, 0,
/// +1) shares the rest: 1/2 on the border, 1 at `half_width` inside.
inline double own_weight(double inside_mm, double period_mm, double half_width, int& neighbour) {
  if (inside_mm < half_width) {
    neighbour = -1;
    return smooth(0.5 + 0.5 * inside_mm / half_width);
  }
  if (inside_mm > period_mm - half_width) {
    neighbour = 1;
    return smooth(0.5 + 0.5 * (period_mm - inside_mm) / half_width);
  }
  neighbour = 0;
  return 1.0;
}

}  // namespace

PhotoGround::PhotoGround(const std::string& file, double mm_per_pixel, std::uint64_t seed)
    : PhotoGround(load_grey(file), mm_per_pixel, seed, file) {}

PhotoGround::PhotoGround(const cv::Mat& grey, double mm_per_pixel, std::uint64_t seed, const std::string& name)
    : mm_per_pixel_(mm_per_pixel), seed_(seed) {
  if (grey.type() != CV_8UC1 || grey.empty())
    throw std::invalid_argument("simulator: ground photo '" + name + "' must be an 8-bit grey image");
  if (grey.rows != grey.cols || grey.rows < 16)
    throw std::invalid_argument("simulator: ground photo '" + name + "' is " + std::to_string(grey.cols) + "x" +
                                std::to_string(grey.rows) +
                                " px; it must be square (the tiles turn by 90 deg) and at least 16 px: crop it "
                                "to a seamless square");
  if (!(mm_per_pixel >= GroundSpec::kMinPhotoMmPerPixel && mm_per_pixel <= GroundSpec::kMaxPhotoMmPerPixel))
    throw std::invalid_argument("simulator: ground photo '" + name + "': mm per photo pixel " +
                                std::to_string(mm_per_pixel) + " must be in [0.01, 5] (real asphalt: about 0.1-0.3)");
  n_ = grey.rows;
  period_mm_ = n_ * mm_per_pixel_;
  blend_half_width_mm_ = period_mm_ * kBlendHalfWidthFraction;
  double sum = 0.0;
  for (int r = 0; r < n_; ++r) {
    const auto* p = grey.ptr<std::uint8_t>(r);
    for (int c = 0; c < n_; ++c) sum += p[c];
  }
  const double mean_grey = sum / (static_cast<double>(n_) * n_);
  if (!(mean_grey >= 1.0))
    throw std::invalid_argument("simulator: ground photo '" + name + "' is black (mean grey " +
                                std::to_string(mean_grey) + "); give a photo of the ground");
  // reflectance = grey x (procedural mean / photo mean): the same mean
  // brightness as the procedural asphalt, the photo's relative contrast.
  const double scale = kProceduralMeanReflectance / mean_grey;
  texels_.resize(static_cast<std::size_t>(n_) * static_cast<std::size_t>(n_));
  for (int r = 0; r < n_; ++r) {
    const auto* p = grey.ptr<std::uint8_t>(r);
    for (int c = 0; c < n_; ++c)
      texels_[static_cast<std::size_t>(r) * static_cast<std::size_t>(n_) + static_cast<std::size_t>(c)] =
          static_cast<float>(p[c] * scale);
  }
  mean_ = kProceduralMeanReflectance;
}

PhotoGround::TileMap PhotoGround::tile_map(std::int64_t tx, std::int64_t ty) const {
  const std::uint64_t h = detail::hash_cell(seed_, kTileSalt, tx, ty);
  const auto n = static_cast<std::uint64_t>(n_);
  TileMap m;
  m.offset_u = static_cast<double>(h % n);
  m.offset_v = static_cast<double>((h >> 21) % n);
  m.symmetry = static_cast<int>((h >> 42) & 7u);
  return m;
}

float PhotoGround::sample(double u, double v) const {
  // Pixel centres at k + 1/2; the photo wraps around (it is seamless).
  const double fu = u - 0.5;
  const double fv = v - 0.5;
  const double gu = std::floor(fu);
  const double gv = std::floor(fv);
  const auto tu = static_cast<float>(fu - gu);
  const auto tv = static_cast<float>(fv - gv);
  const std::int64_t n = n_;
  auto wrap = [n](double g) {
    std::int64_t k = static_cast<std::int64_t>(g) % n;
    return k < 0 ? k + n : k;
  };
  const std::int64_t u0 = wrap(gu);
  const std::int64_t v0 = wrap(gv);
  const std::int64_t u1 = u0 + 1 == n ? 0 : u0 + 1;
  const std::int64_t v1 = v0 + 1 == n ? 0 : v0 + 1;
  const float* r0 = texels_.data() + v0 * n;
  const float* r1 = texels_.data() + v1 * n;
  const float a = r0[u0] + tu * (r0[u1] - r0[u0]);
  const float b = r1[u0] + tu * (r1[u1] - r1[u0]);
  return a + tv * (b - a);
}

float PhotoGround::tile_value(const TileMap& m, std::int64_t tx, std::int64_t ty, double x_mm, double y_mm) const {
  // Photo pixels from the tile's corner (negative or beyond n just outside it).
  double u = (x_mm - static_cast<double>(tx) * period_mm_) / mm_per_pixel_;
  double v = (y_mm - static_cast<double>(ty) * period_mm_) / mm_per_pixel_;
  if ((m.symmetry & 1) != 0) u = -u;
  if ((m.symmetry & 2) != 0) v = -v;
  if ((m.symmetry & 4) != 0) std::swap(u, v);
  return sample(u + m.offset_u, v + m.offset_v);
}

void PhotoGround::render_rows(const RasterGrid& grid, int row_begin, int row_end, float* out) const {
  // The tiles the strip can touch (one more on each side for the blend), so
  // each tile's map is hashed once per strip, not per sample.
  double x_lo = 1e300, x_hi = -1e300, y_lo = 1e300, y_hi = -1e300;
  for (const double j : {-1.0, static_cast<double>(grid.cols)}) {
    for (const double i : {static_cast<double>(row_begin) - 1.0, static_cast<double>(row_end)}) {
      double x = 0.0, y = 0.0;
      grid.to_world(j, i, x, y);
      x_lo = std::min(x_lo, x);
      x_hi = std::max(x_hi, x);
      y_lo = std::min(y_lo, y);
      y_hi = std::max(y_hi, y);
    }
  }
  const auto tx_lo = static_cast<std::int64_t>(std::floor(x_lo / period_mm_)) - 1;
  const auto ty_lo = static_cast<std::int64_t>(std::floor(y_lo / period_mm_)) - 1;
  const auto nx = static_cast<std::int64_t>(std::floor(x_hi / period_mm_)) + 2 - tx_lo;
  const auto ny = static_cast<std::int64_t>(std::floor(y_hi / period_mm_)) + 2 - ty_lo;
  std::vector<TileMap> maps(static_cast<std::size_t>(nx * ny));
  for (std::int64_t b = 0; b < ny; ++b)
    for (std::int64_t a = 0; a < nx; ++a) maps[static_cast<std::size_t>(b * nx + a)] = tile_map(tx_lo + a, ty_lo + b);
  auto value = [&](std::int64_t tx, std::int64_t ty, double x, double y) {
    const std::int64_t a = std::clamp<std::int64_t>(tx - tx_lo, 0, nx - 1);
    const std::int64_t b = std::clamp<std::int64_t>(ty - ty_lo, 0, ny - 1);
    return static_cast<double>(tile_value(maps[static_cast<std::size_t>(b * nx + a)], tx, ty, x, y));
  };

  const double mean = mean_;
  const double hw = blend_half_width_mm_;
  for (int r = row_begin; r < row_end; ++r) {
    float* row = out + static_cast<std::ptrdiff_t>(r - row_begin) * grid.cols;
    for (int c = 0; c < grid.cols; ++c) {
      double x = 0.0, y = 0.0;
      grid.to_world(c, r, x, y);
      const auto tx = static_cast<std::int64_t>(std::floor(x / period_mm_));
      const auto ty = static_cast<std::int64_t>(std::floor(y / period_mm_));
      int sx = 0, sy = 0;
      const double ax = own_weight(x - static_cast<double>(tx) * period_mm_, period_mm_, hw, sx);
      const double ay = own_weight(y - static_cast<double>(ty) * period_mm_, period_mm_, hw, sy);
      if (sx == 0 && sy == 0) {
        row[c] = std::clamp(static_cast<float>(value(tx, ty, x, y)), 0.0f, 1.0f);
        continue;
      }
      // Variance-preserving blend (Heitz & Neyret 2018, Burley 2019): for
      // independent textures of equal variance, mean + sum w_i (T_i - mean) /
      // sqrt(sum w_i^2) keeps the mean and the variance of every frequency
      // band, where a plain cross-fade would halve the variance mid-band.
      double sum = ax * ay * (value(tx, ty, x, y) - mean);
      double norm = ax * ay * ax * ay;
      if (sx != 0) {
        const double w = (1.0 - ax) * ay;
        sum += w * (value(tx + sx, ty, x, y) - mean);
        norm += w * w;
      }
      if (sy != 0) {
        const double w = ax * (1.0 - ay);
        sum += w * (value(tx, ty + sy, x, y) - mean);
        norm += w * w;
      }
      if (sx != 0 && sy != 0) {
        const double w = (1.0 - ax) * (1.0 - ay);
        sum += w * (value(tx + sx, ty + sy, x, y) - mean);
        norm += w * w;
      }
      row[c] = std::clamp(static_cast<float>(mean + sum / std::sqrt(norm)), 0.0f, 1.0f);
    }
  }
}

}  // namespace gvs::drivers::sim
