// Procedural asphalt: aggregate stones 1-8 mm in a bitumen matrix with pores,
// sand and fine grain. Every feature lives on a jittered world grid of its
// size class and is hashed from its 64-bit cell index and the seed, so the
// surface is deterministic and never repeats. Rendering stamps each feature
// into the raster (cost grows with the raster area, not with a neighbourhood
// search per sample).
#include "asphalt.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <string>

#include "hash.hpp"

namespace gvs::drivers::sim {
namespace {

constexpr double kPi = std::numbers::pi;

struct WorldPoint {
  double x;
  double y;
};

/// x-extent of a convex quadrilateral within the band y in [ya, yb]; false when
/// they do not meet.
bool x_range_in_band(const std::array<WorldPoint, 4>& quad, double ya, double yb, double& x_min,
                     double& x_max) {
  x_min = std::numeric_limits<double>::infinity();
  x_max = -std::numeric_limits<double>::infinity();
  for (std::size_t k = 0; k < 4; ++k) {
    const WorldPoint& p = quad[k];
    const WorldPoint& q = quad[(k + 1) % 4];
    if (p.y >= ya && p.y <= yb) {
      x_min = std::min(x_min, p.x);
      x_max = std::max(x_max, p.x);
    }
    for (const double y : {ya, yb}) {
      if ((p.y - y) * (q.y - y) < 0.0) {
        const double x = p.x + (q.x - p.x) * (y - p.y) / (q.y - p.y);
        x_min = std::min(x_min, x);
        x_max = std::max(x_max, x);
      }
    }
  }
  return x_min <= x_max;
}

/// Smooth value noise on a coarse world lattice (used per feature, not per
/// sample); `wrap` maps lattice indices to the hashed ones (periodic texture).
template <typename Wrap>
double value_noise(std::uint64_t seed, double x, double y, double lattice_mm, const Wrap& wrap) {
  const double fx = x / lattice_mm;
  const double fy = y / lattice_mm;
  const double gx = std::floor(fx);
  const double gy = std::floor(fy);
  const auto ix = static_cast<std::int64_t>(gx);
  const auto iy = static_cast<std::int64_t>(gy);
  auto val = [&](std::int64_t a, std::int64_t b) {
    return static_cast<double>(detail::hash_cell(seed, 99, wrap(a), wrap(b)) >> 11) * 0x1.0p-53 * 2.0 - 1.0;
  };
  const double tx = fx - gx;
  const double ty = fy - gy;
  const double sx = tx * tx * (3 - 2 * tx);
  const double sy = ty * ty * (3 - 2 * ty);
  const double top = val(ix, iy) + (val(ix + 1, iy) - val(ix, iy)) * sx;
  const double bot = val(ix, iy + 1) + (val(ix + 1, iy + 1) - val(ix, iy + 1)) * sx;
  return top + (bot - top) * sy;
}

/// floor() for moderate values without a libm call (baseline x86-64 has no
/// SSE4.1 roundsd).
inline int fast_floor(double x) {
  const int i = static_cast<int>(x);
  return x < static_cast<double>(i) ? i - 1 : i;
}

/// One stamped feature, in raster units.
struct Feature {
  double cj = 0.0;  ///< centre, raster column
  double ci = 0.0;  ///< centre, raster row
  float exx = 1.0f;  ///< raster steps (dj, di) -> feature units (ex, ey)
  float exy = 0.0f;
  float eyx = 0.0f;
  float eyy = 1.0f;
  std::array<float, 4> harm_c{};  ///< edge = 1 + sum_k c_k Re z^k + s_k Im z^k, k = 2..5
  std::array<float, 4> harm_s{};
  float edge_max = 1.0f;
  float bound_rows = 1.0f;  ///< bounding radius in raster rows
  float bound_cols = 1.0f;  ///< ... and columns
  float grey = 0.0f;
  float rim = 0.0f;  ///< darkening towards the rim (LED ring light on a rounded stone)
  float tilt_x = 0.0f;
  float tilt_y = 0.0f;
};

}  // namespace

AsphaltTexture::AsphaltTexture(std::uint64_t seed) : seed_(seed) {
  // (kind, r_min, r_max, nominal cover, occupancy). Stones 1-8 mm diameter,
  // log-uniform radius in each class, so small stones are far more numerous.
  const std::array<FeatureClass, 7> spec{{
      {Kind::stone, 2.6, 4.0, 0.22, 0.8, 0.0},
      {Kind::stone, 1.7, 2.6, 0.20, 0.8, 0.0},
      {Kind::stone, 1.1, 1.7, 0.18, 0.8, 0.0},
      {Kind::stone, 0.7, 1.1, 0.15, 0.8, 0.0},
      {Kind::stone, 0.5, 0.7, 0.10, 0.8, 0.0},
      {Kind::pore, 0.12, 0.5, 0.05, 0.6, 0.0},
      {Kind::sand, 0.07, 0.25, 0.12, 0.8, 0.0},
  }};
  for (FeatureClass c : spec) {
    // E[R^2] of a log-uniform radius, mean aspect 0.8: cover = occ * pi * E[R^2] * 0.8 / cell^2.
    const double mean_r2 = (c.r_max_mm * c.r_max_mm - c.r_min_mm * c.r_min_mm) /
                           (2.0 * std::log(c.r_max_mm / c.r_min_mm));
    c.cell_mm = std::sqrt(c.occupancy * kPi * mean_r2 * 0.8 / c.cover);
    classes_.push_back(c);
  }
}

AsphaltTexture::AsphaltTexture(std::uint64_t seed, double period_mm) : AsphaltTexture(seed) {
  const double steps = period_mm / kPeriodStepMm;
  if (!(steps >= 1.0) || std::abs(steps - std::round(steps)) > 1e-9)
    throw std::invalid_argument("simulator: texture period must be a positive multiple of 36 mm, got " +
                                std::to_string(period_mm));
  period_mm_ = period_mm;
  // A whole number of cells per period (cover changes by a few per cent at most).
  for (FeatureClass& c : classes_) c.cell_mm = period_mm / std::max(1.0, std::round(period_mm / c.cell_mm));
}

std::int64_t AsphaltTexture::wrap(std::int64_t index, double lattice_mm) const {
  if (period_mm_ <= 0.0) return index;
  const auto n = static_cast<std::int64_t>(std::llround(period_mm_ / lattice_mm));
  return ((index % n) + n) % n;
}

void AsphaltTexture::render_rows(const RasterGrid& grid, int row_begin, int row_end,
                                 float* out) const {
  const auto n = static_cast<std::size_t>(row_end - row_begin) * static_cast<std::size_t>(grid.cols);
  std::fill(out, out + n, -1.0f);
  for (std::size_t k = 0; k < classes_.size(); ++k) stamp_class(k, grid, row_begin, row_end, out);
  if (period_mm_ > 0.0) {
    add_grain_periodic(grid, row_begin, row_end, out);
  } else {
    add_grain(grid, row_begin, row_end, out);
  }
}

namespace {

/// 32-bit lattice hash -> [-1, 1). Lattice indices wrap at 2^32 cells
/// (515 km for the fine lattice): no repetition within any run.
inline float lattice_value(std::uint32_t key, std::uint32_t ix, std::uint32_t iy) {
  std::uint32_t h = (ix * 0x9E3779B1u) ^ (iy * 0x85EBCA77u) ^ key;
  h ^= h >> 15;
  h *= 0x2C1B3C6Du;
  h ^= h >> 12;
  h *= 0x297A2D39u;
  h ^= h >> 15;
  return static_cast<float>(static_cast<std::int32_t>(h >> 8)) * 0x1.0p-23f - 1.0f;
}

/// Smoothstep-weighted bilinear blend of four lattice values (value noise).
inline float smooth_blend(float v00, float v10, float v01, float v11, float tx, float ty) {
  const float sx = tx * tx * (3.0f - 2.0f * tx);
  const float sy = ty * ty * (3.0f - 2.0f * ty);
  const float a = v00 + (v10 - v00) * sx;
  const float b = v01 + (v11 - v01) * sx;
  return a + (b - a) * sy;
}

/// A stamped sample `v` (< 0: still bare binder) with the fine (nf) and
/// medium (nm) grain: strong grain on the binder, a weak speckle on stones.
/// Branch-free, so that the row loop vectorises.
inline float with_grain(float v, float nf, float nm) {
  const float binder = AsphaltTexture::kBitumen * (1.0f + 0.5f * nf + 0.3f * nm);
  const float stone = v * (1.0f + 0.18f * nf + 0.06f * nm);
  const float is_binder = static_cast<float>(v < 0.0f);
  return stone + is_binder * (binder - stone);
}

/// Smooth value noise at lattice position (base + f) where f is a small
/// float offset (branch-free, vectorisable).
inline float value_noise_at(std::uint32_t key, std::uint32_t bx, std::uint32_t by, float fx,
                            float fy) {
  int ix = static_cast<int>(fx);
  ix -= static_cast<int>(fx < static_cast<float>(ix));
  int iy = static_cast<int>(fy);
  iy -= static_cast<int>(fy < static_cast<float>(iy));
  const float tx = fx - static_cast<float>(ix);
  const float ty = fy - static_cast<float>(iy);
  const std::uint32_t x0 = bx + static_cast<std::uint32_t>(ix);
  const std::uint32_t y0 = by + static_cast<std::uint32_t>(iy);
  return smooth_blend(lattice_value(key, x0, y0), lattice_value(key, x0 + 1u, y0), lattice_value(key, x0, y0 + 1u),
                      lattice_value(key, x0 + 1u, y0 + 1u), tx, ty);
}

/// Integer lattice base and float offset of a world coordinate (mm).
void lattice_split(double mm, double lattice_mm, std::uint32_t& base, float& offset) {
  const double f = mm / lattice_mm;
  const double g = std::floor(f);
  base = static_cast<std::uint32_t>(static_cast<std::int64_t>(g));
  offset = static_cast<float>(f - g);
}

}  // namespace

void AsphaltTexture::add_grain(const RasterGrid& grid, int row_begin, int row_end,
                               float* out) const {
  // Two octaves of value noise on world lattices: fine mineral grain / filler
  // (kFineLatticeMm) and a medium mottle (kMediumLatticeMm). The binder
  // (still uncovered samples) gets strong grain, the stones a weak speckle.
  const auto key_fine = static_cast<std::uint32_t>(detail::mix64(seed_ ^ 0xF19EULL));
  const auto key_medium = static_cast<std::uint32_t>(detail::mix64(seed_ ^ 0x3ED1ULL));
  double x1 = 0.0, y1 = 0.0, x0 = 0.0, y0 = 0.0;
  grid.to_world(0.0, 0.0, x0, y0);
  grid.to_world(1.0, 0.0, x1, y1);
  const double dx = x1 - x0;
  const double dy = y1 - y0;
  const auto sfx = static_cast<float>(dx / kFineLatticeMm);
  const auto sfy = static_cast<float>(dy / kFineLatticeMm);
  const auto smx = static_cast<float>(dx / kMediumLatticeMm);
  const auto smy = static_cast<float>(dy / kMediumLatticeMm);
  for (int r = row_begin; r < row_end; ++r) {
    float* row = out + static_cast<std::ptrdiff_t>(r - row_begin) * grid.cols;
    grid.to_world(0.0, r, x0, y0);
    std::uint32_t bfx, bfy, bmx, bmy;
    float ofx, ofy, omx, omy;
    lattice_split(x0, kFineLatticeMm, bfx, ofx);
    lattice_split(y0, kFineLatticeMm, bfy, ofy);
    lattice_split(x0, kMediumLatticeMm, bmx, omx);
    lattice_split(y0, kMediumLatticeMm, bmy, omy);
    for (int c = 0; c < grid.cols; ++c) {
      const auto fc = static_cast<float>(c);
      const float nf = value_noise_at(key_fine, bfx, bfy, ofx + fc * sfx, ofy + fc * sfy);
      const float nm = value_noise_at(key_medium, bmx, bmy, omx + fc * smx, omy + fc * smy);
      row[c] = with_grain(row[c], nf, nm);
    }
  }
}

void AsphaltTexture::add_grain_periodic(const RasterGrid& grid, int row_begin, int row_end,
                                        float* out) const {
  // As add_grain, with every lattice index wrapped to the period (slower:
  // used once, to render a periodic tile).
  const auto key_fine = static_cast<std::uint32_t>(detail::mix64(seed_ ^ 0xF19EULL));
  const auto key_medium = static_cast<std::uint32_t>(detail::mix64(seed_ ^ 0x3ED1ULL));
  const auto n_fine = static_cast<int>(std::llround(period_mm_ / kFineLatticeMm));
  const auto n_medium = static_cast<int>(std::llround(period_mm_ / kMediumLatticeMm));
  auto noise = [](std::uint32_t key, double x_mm, double y_mm, double lattice_mm, int n) {
    const double fx = x_mm / lattice_mm;
    const double fy = y_mm / lattice_mm;
    const int gx = fast_floor(fx);
    const int gy = fast_floor(fy);
    auto wrapped = [n](int k) {
      k %= n;
      return static_cast<std::uint32_t>(k < 0 ? k + n : k);
    };
    const std::uint32_t x0 = wrapped(gx), x1 = wrapped(gx + 1), y0 = wrapped(gy), y1 = wrapped(gy + 1);
    return smooth_blend(lattice_value(key, x0, y0), lattice_value(key, x1, y0), lattice_value(key, x0, y1),
                        lattice_value(key, x1, y1), static_cast<float>(fx - gx), static_cast<float>(fy - gy));
  };
  for (int r = row_begin; r < row_end; ++r) {
    float* row = out + static_cast<std::ptrdiff_t>(r - row_begin) * grid.cols;
    for (int c = 0; c < grid.cols; ++c) {
      double x = 0.0, y = 0.0;
      grid.to_world(c, r, x, y);
      const float nf = noise(key_fine, x, y, kFineLatticeMm, n_fine);
      const float nm = noise(key_medium, x, y, kMediumLatticeMm, n_medium);
      row[c] = with_grain(row[c], nf, nm);
    }
  }
}

void AsphaltTexture::stamp_class(std::size_t class_index, const RasterGrid& grid, int row_begin,
                                 int row_end, float* out) const {
  const FeatureClass& fc = classes_[class_index];
  const double hv = grid.spacing_mm;
  const double hu = grid.spacing_u_mm;
  const double cell = fc.cell_mm;
  // The strip (grown by the largest feature) as a world quadrilateral.
  const double j0 = -0.5 - fc.r_max_mm * 1.45 / hu;
  const double j1 = grid.cols - 0.5 + fc.r_max_mm * 1.45 / hu;
  const double i0 = row_begin - 0.5 - fc.r_max_mm * 1.45 / hv;
  const double i1 = row_end - 0.5 + fc.r_max_mm * 1.45 / hv;
  std::array<WorldPoint, 4> quad{};
  grid.to_world(j0, i0, quad[0].x, quad[0].y);
  grid.to_world(j1, i0, quad[1].x, quad[1].y);
  grid.to_world(j1, i1, quad[2].x, quad[2].y);
  grid.to_world(j0, i1, quad[3].x, quad[3].y);
  double y_lo = quad[0].y;
  double y_hi = quad[0].y;
  for (const auto& p : quad) {
    y_lo = std::min(y_lo, p.y);
    y_hi = std::max(y_hi, p.y);
  }
  const auto iy_begin = static_cast<std::int64_t>(std::floor(y_lo / cell));
  const auto iy_end = static_cast<std::int64_t>(std::floor(y_hi / cell));
  const int cols = grid.cols;
  // Outline roughness (harmonics 2..5 of the radius): angular crushed stone,
  // rounder sand and pores.
  const float rough = fc.kind == Kind::stone ? 0.5f : 0.4f;
  const double aspect_min = fc.kind == Kind::stone ? 0.6 : 0.7;

  for (std::int64_t iy = iy_begin; iy <= iy_end; ++iy) {
    double x_lo = 0.0;
    double x_hi = 0.0;
    if (!x_range_in_band(quad, static_cast<double>(iy) * cell, static_cast<double>(iy + 1) * cell,
                         x_lo, x_hi))
      continue;
    const auto ix_begin = static_cast<std::int64_t>(std::floor(x_lo / cell));
    const auto ix_end = static_cast<std::int64_t>(std::floor(x_hi / cell));
    for (std::int64_t ix = ix_begin; ix <= ix_end; ++ix) {
      detail::Rng rng(detail::hash_cell(seed_, class_index, wrap(ix, cell), wrap(iy, cell)));
      if (rng.uniform() >= fc.occupancy) continue;
      const double wx = (static_cast<double>(ix) + rng.uniform()) * cell;
      const double wy = (static_cast<double>(iy) + rng.uniform()) * cell;
      Feature f;
      grid.to_raster(wx, wy, f.cj, f.ci);
      const double radius_mm = fc.r_min_mm * std::exp(rng.uniform() * std::log(fc.r_max_mm / fc.r_min_mm));
      const double aspect = aspect_min + (1.0 - aspect_min) * rng.uniform();
      // Orientation: a random unit vector (no trigonometry per feature).
      double ox = rng.uniform() - 0.5;
      double oy = rng.uniform() - 0.5;
      const double on = std::hypot(ox, oy) + 1e-12;
      ox /= on;
      oy /= on;
      // Relative to the raster axes (raster u axis = (ux, uy)), then raster
      // steps -> feature units: ex = exx dj + exy di, ey = eyx dj + eyy di.
      const double cr = ox * grid.ux + oy * grid.uy;
      const double sr = oy * grid.ux - ox * grid.uy;
      const double a_mm = radius_mm;
      const double b_mm = radius_mm * aspect;
      f.exx = static_cast<float>(hu * cr / a_mm);
      f.exy = static_cast<float>(hv * sr / a_mm);
      f.eyx = static_cast<float>(-hu * sr / b_mm);
      f.eyy = static_cast<float>(hv * cr / b_mm);
      float amp_sum = 0.0f;
      for (std::size_t m = 0; m < 4; ++m) {
        // Harmonic k = m + 2 with amplitude up to rough / k, random phase.
        const float limit = rough / static_cast<float>(m + 2);
        f.harm_c[m] = limit * (rng.uniformf() - 0.5f);
        f.harm_s[m] = limit * (rng.uniformf() - 0.5f);
        amp_sum += std::abs(f.harm_c[m]) + std::abs(f.harm_s[m]);
      }
      f.edge_max = 1.0f + amp_sum;
      f.bound_rows = static_cast<float>(radius_mm / hv) * f.edge_max + 1.0f;
      f.bound_cols = static_cast<float>(radius_mm / hu) * f.edge_max + 1.0f;
      switch (fc.kind) {
        case Kind::stone: {
          const double type = rng.uniform();
          double g = 0.0;
          if (type < 0.12) {
            g = 0.20 + 0.035 * static_cast<double>(rng.normal());  // dark basalt
          } else if (type < 0.25) {
            g = 0.55 + 0.07 * static_cast<double>(rng.normal());  // light quartzite / limestone
          } else {
            g = 0.40 + 0.07 * static_cast<double>(rng.normal());  // greywacke, granite
          }
          // Slow variation of the surface (wear, dust), about +-8 % over ~12 mm.
          g *= 1.0 + 0.08 * value_noise(seed_, wx, wy, kWearLatticeMm,
                                        [this](std::int64_t k) { return wrap(k, kWearLatticeMm); });
          f.grey = static_cast<float>(std::clamp(g, 0.1, 0.85));
          f.rim = 0.25f + 0.15f * rng.uniformf();
          f.tilt_x = 0.12f * (rng.uniformf() - 0.5f);
          f.tilt_y = 0.12f * (rng.uniformf() - 0.5f);
          break;
        }
        case Kind::pore:
          f.grey = 0.015f + 0.02f * rng.uniformf();
          f.rim = -1.5f;  // brighter towards the rim: value = grey (1 + 1.5 rho^2)
          break;
        case Kind::sand:
          f.grey = 0.16f + 0.3f * rng.uniformf();
          f.rim = 0.3f;
          break;
      }
      const int r_lo = std::max(row_begin, static_cast<int>(std::ceil(f.ci - static_cast<double>(f.bound_rows))));
      const int r_hi = std::min(row_end - 1, static_cast<int>(std::floor(f.ci + static_cast<double>(f.bound_rows))));
      const int c_lo = std::max(0, static_cast<int>(std::ceil(f.cj - static_cast<double>(f.bound_cols))));
      const int c_hi = std::min(cols - 1, static_cast<int>(std::floor(f.cj + static_cast<double>(f.bound_cols))));
      const float e2max = f.edge_max * f.edge_max;
      const float exx = f.exx, exy = f.exy, eyx = f.eyx, eyy = f.eyy;
      const float hc0 = f.harm_c[0], hc1 = f.harm_c[1], hc2 = f.harm_c[2], hc3 = f.harm_c[3];
      const float hs0 = f.harm_s[0], hs1 = f.harm_s[1], hs2 = f.harm_s[2], hs3 = f.harm_s[3];
      const float grey = f.grey, rim = f.rim, tilt_x = f.tilt_x, tilt_y = f.tilt_y;
      // Row span of the bounding ellipse rho <= edge_max: A dx^2 + B dx + C <= 0.
      const float qa = exx * exx + eyx * eyx;
      const float qb = 2.0f * (exx * exy + eyx * eyy);
      const float qc = exy * exy + eyy * eyy;
      for (int r = r_lo; r <= r_hi; ++r) {
        float* row = out + static_cast<std::ptrdiff_t>(r - row_begin) * cols;
        const auto dy = static_cast<float>(static_cast<double>(r) - f.ci);
        const float b = qb * dy;
        const float disc = b * b - 4.0f * qa * (qc * dy * dy - e2max);
        if (disc <= 0.0f) continue;
        const float root = std::sqrt(disc);
        const double span_lo = f.cj + static_cast<double>((-b - root) / (2.0f * qa));
        const double span_hi = f.cj + static_cast<double>((-b + root) / (2.0f * qa));
        const int cs = std::max(c_lo, -fast_floor(-span_lo));
        const int ce = std::min(c_hi, fast_floor(span_hi));
        const auto dx0 = static_cast<float>(static_cast<double>(cs) - f.cj);
        // Branch-free so that it vectorises: every sample of the span is
        // evaluated, and written only when inside and still uncovered.
        for (int c = cs; c <= ce; ++c) {
          const float dx = dx0 + static_cast<float>(c - cs);
          const float ex = exx * dx + exy * dy;
          const float ey = eyx * dx + eyy * dy;
          const float rho2 = ex * ex + ey * ey + 1e-12f;
          const float inv = 1.0f / std::sqrt(rho2);
          const float zr = ex * inv;
          const float zi = ey * inv;
          float pr = zr * zr - zi * zi;  // Re, Im of z^2
          float pi = 2.0f * zr * zi;
          float edge = 1.0f + hc0 * pr + hs0 * pi;
          float nr = pr * zr - pi * zi;  // z^3
          pi = pr * zi + pi * zr;
          pr = nr;
          edge += hc1 * pr + hs1 * pi;
          nr = pr * zr - pi * zi;  // z^4
          pi = pr * zi + pi * zr;
          pr = nr;
          edge += hc2 * pr + hs2 * pi;
          nr = pr * zr - pi * zi;  // z^5
          pi = pr * zi + pi * zr;
          pr = nr;
          edge += hc3 * pr + hs3 * pi;
          const float e2 = edge * edge;
          const float value = std::max(0.0f, grey * (1.0f - rim * rho2 / e2 + tilt_x * ex + tilt_y * ey));
          const float cur = row[c];
          row[c] = (rho2 < e2 && cur < 0.0f) ? value : cur;
        }
      }
    }
  }
}

}  // namespace gvs::drivers::sim
