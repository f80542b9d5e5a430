// The live fast render's path integrals (docs/simulator.md, "Live source").
// When the view only translates during a piece of path (no rotation), every
// pixel moves by the same raster vector (dj, di), so the mean along the
// piece is one box filter of the raster along its rows, the same for every
// pixel: computed once per raster sample from the prefix sums, then sampled
// bilinearly at each pixel's start point: one bilinear lookup per pixel and
// piece (plus one pass over the raster) instead of the exact render's
// interpolated prefix differences per pixel.
#include <algorithm>
#include <cmath>

#include <opencv2/core.hpp>

#include "exposure.hpp"
#include "parallel.hpp"

namespace gvs::drivers::sim {
namespace {

/// Largest spread (raster px) of a piece's path vector over the image for it
/// to count as a translation.
constexpr double kTranslationTolerance = 0.05;

/// Prefix integral of one row at fractional column k + t (as in exposure.cpp).
inline float prefix_at(const float* row, int k, float t) {
  return row[2 * k] + t * (row[2 * k + 1] + 0.5f * t * (row[2 * k + 3] - row[2 * k + 1]));
}

}  // namespace

bool integrate_translating(const float* cells, int rows, int cols,
                           const std::vector<ExposureRenderer::Knot>& knots,
                           const std::vector<std::size_t>& interval_begin, float offset, bool parallel,
                           std::vector<float>& box, cv::Mat& out) {
  const int height = out.rows;
  const int width = out.cols;
  // Every piece must translate and stay within half a raster row.
  double lit_s = 0.0;
  for (std::size_t iv = 0; iv + 1 < interval_begin.size(); ++iv) {
    for (std::size_t k = interval_begin[iv] + 1; k < interval_begin[iv + 1]; ++k) {
      const ExposureRenderer::Knot& a = knots[k - 1];
      const ExposureRenderer::Knot& b = knots[k];
      const double spread_j = (height - 1) * std::abs(b.jr - a.jr) + (width - 1) * std::abs(b.jc - a.jc);
      const double spread_i = (height - 1) * std::abs(b.ir - a.ir) + (width - 1) * std::abs(b.ic - a.ic);
      if (spread_j > kTranslationTolerance || spread_i > kTranslationTolerance) return false;
      const double di = (b.i00 - a.i00) + 0.5 * (height - 1) * (b.ir - a.ir) + 0.5 * (width - 1) * (b.ic - a.ic);
      if (std::abs(di) > 0.5) return false;
      lit_s += b.t_s - a.t_s;
    }
  }
  if (!(lit_s > 0.0)) return false;

  box.resize(static_cast<std::size_t>(rows) * static_cast<std::size_t>(cols));
  const double rc = 0.5 * (height - 1);
  const double cc = 0.5 * (width - 1);
  for (std::size_t iv = 0; iv + 1 < interval_begin.size(); ++iv) {
    for (std::size_t k = interval_begin[iv] + 1; k < interval_begin[iv + 1]; ++k) {
      const ExposureRenderer::Knot& a = knots[k - 1];
      const ExposureRenderer::Knot& b = knots[k];
      // The piece's path vector at the image centre.
      const double dj = (b.j00 - a.j00) + rc * (b.jr - a.jr) + cc * (b.jc - a.jc);
      const double di = (b.i00 - a.i00) + rc * (b.ir - a.ir) + cc * (b.ic - a.ic);
      const auto weight = static_cast<float>((b.t_s - a.t_s) / lit_s);
      // box(j, i): mean of the row's linear interpolant over [j, j + dj]; a
      // piece shorter than a raster px is a sample at its middle instead.
      const bool along = std::abs(dj) >= 1.0;
      const double shift_j = along ? 0.0 : 0.5 * dj;
      const double shift_i = 0.5 * di;  // integrated along the piece's mid row
      // Raster samples the pixels' start points touch (the image corners
      // bound them): only those are filtered. The raster's margin keeps them
      // and their path ends inside; if not, the exact per-pixel path runs.
      double jlo = 1e300, jhi = -1e300, ilo = 1e300, ihi = -1e300;
      for (const double r : {0.0, height - 1.0}) {
        for (const double c : {0.0, width - 1.0}) {
          const double j = a.j00 + r * a.jr + c * a.jc + shift_j;
          const double i = a.i00 + r * a.ir + c * a.ic + shift_i;
          jlo = std::min(jlo, j);
          jhi = std::max(jhi, j);
          ilo = std::min(ilo, i);
          ihi = std::max(ihi, i);
        }
      }
      // (One sample more on each side than the corners need: float rounding below.)
      if (jlo < 1.0 || ilo < 1.0 || jhi + 2.0 > cols - 1.001 || ihi + 2.0 > rows - 1.001 ||
          (along && (jlo + dj < 2.0 || jhi + 2.0 + dj > cols - 1.001))) {
        return false;
      }
      const int j_first = static_cast<int>(jlo) - 1;
      const int j_last = static_cast<int>(jhi) + 2;
      const int i_first = static_cast<int>(ilo) - 1;
      const int i_last = static_cast<int>(ihi) + 2;
      for_strips(parallel, cv::Range(i_first, i_last + 1), [&](const cv::Range& range) {
        const auto inv = static_cast<float>(1.0 / dj);
        for (int i = range.start; i < range.end; ++i) {
          const float* row = cells + 2 * static_cast<std::ptrdiff_t>(i) * cols;
          float* dst = box.data() + static_cast<std::ptrdiff_t>(i) * cols;
          if (!along) {
            for (int j = j_first; j <= j_last; ++j) dst[j] = row[2 * j + 1];
            continue;
          }
          // The end point j + dj has the same fraction for every j.
          const int whole = static_cast<int>(std::floor(dj));
          const auto t = static_cast<float>(dj - whole);
          for (int j = j_first; j <= j_last; ++j) {
            const int ke = j + whole;
            dst[j] = (prefix_at(row, ke, t) - row[2 * j]) * inv;
          }
        }
      });
      // Bilinear sample of box at each pixel's start point (+ the shifts),
      // column by column: down an image column the start point moves along
      // the raster rows (the view's motion is mostly along the image
      // columns), so the reads stay in a few cache lines.
      const bool first = k == interval_begin.front() + 1;  // the first piece writes, the others add
      const float* origin = box.data() + static_cast<std::ptrdiff_t>(i_first) * cols + j_first;
      for_strips(parallel, cv::Range(0, width), [&](const cv::Range& range) {
        const auto jr = static_cast<float>(a.jr);
        const auto ir = static_cast<float>(a.ir);
        const auto out_step = static_cast<std::ptrdiff_t>(out.step1());
        for (int c = range.start; c < range.end; ++c) {
          float* dst = out.ptr<float>(0) + c;
          // Relative to the bounding box's corner, so every offset is >= 0
          // and truncation is floor (float keeps 1e-4 px over a column).
          const auto j0 = static_cast<float>(a.j00 + c * a.jc + shift_j - j_first);
          const auto i0 = static_cast<float>(a.i00 + c * a.ic + shift_i - i_first);
          for (int r = 0; r < height; ++r) {
            const float j = std::max(0.0f, j0 + static_cast<float>(r) * jr);
            const float i = std::max(0.0f, i0 + static_cast<float>(r) * ir);
            const auto kj = static_cast<int>(j);
            const auto ki = static_cast<int>(i);
            const float tj = j - static_cast<float>(kj);
            const float ti = i - static_cast<float>(ki);
            const float* p = origin + static_cast<std::ptrdiff_t>(ki) * cols + kj;
            const float top = p[0] + tj * (p[1] - p[0]);
            const float bottom = p[cols] + tj * (p[cols + 1] - p[cols]);
            const float v = weight * (top + ti * (bottom - top));
            float& o = dst[r * out_step];
            o = first ? offset + v : o + v;
          }
        }
      });
    }
  }
  return true;
}

}  // namespace gvs::drivers::sim
