// Exposure integration. For a frame, the light intervals are cut at knots so
// that between knots every pixel's path over the ground is straight within
// kPathTolerancePx. The asphalt is rendered once into a raster aligned with the
// motion (spacing s/2; s along a long blur), blurred by the pixel/optics PSF, and integrated along
// the raster rows (prefix sums of the linearly interpolated rows). A pixel's
// exposure is then a sum over path segments of differences of prefix sums:
// O(1) per segment, whatever the blur length.
#include "camera_view.hpp"
#include "exposure.hpp"
#include "exposure_knots.hpp"
#include "parallel.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <stdexcept>
#include <string>
#include <type_traits>

#include <opencv2/core/utility.hpp>

namespace gvs::drivers::sim {
namespace {

constexpr float kOffset = 0.3f;  ///< subtracted before the prefix sums (float precision)
constexpr int kMargin = 6;       ///< raster margin for the PSF and interpolation, raster px
constexpr int kPsfRadius = 3;    ///< PSF taps: -3..3 raster px (sigma 1 raster px)
/// Prefix integral of one row at fractional column k + t (linear interpolation between samples).
inline float prefix_at(const float* s, const float* f, int k, float t) {
  return s[2 * k] + t * (f[2 * k] + 0.5f * t * (f[2 * k + 2] - f[2 * k]));
}

class Lookup {
 public:
  Lookup(const float* cells, int rows, int cols) : base_(cells), rows_(rows), cols_(cols) {}

  /// Integral of the bilinear interpolant along row coordinate i from column ja to jb.
  [[nodiscard]] float integral(double ja, double jb, double i) const {
    int r;
    float w;
    row_weight(i, r, w);
    const float* s0 = base_ + 2 * static_cast<std::ptrdiff_t>(r) * cols_;
    const float* s1 = s0 + 2 * cols_;
    int ka;
    float ta;
    col(ja, ka, ta);
    int kb;
    float tb;
    col(jb, kb, tb);
    const float a = (1.0f - w) * prefix_at(s0, s0 + 1, ka, ta) + w * prefix_at(s1, s1 + 1, ka, ta);
    const float b = (1.0f - w) * prefix_at(s0, s0 + 1, kb, tb) + w * prefix_at(s1, s1 + 1, kb, tb);
    return b - a;
  }
  /// Bilinear sample.
  [[nodiscard]] float sample(double j, double i) const {
    int r;
    float w;
    row_weight(i, r, w);
    int k;
    float t;
    col(j, k, t);
    const float* f0 = base_ + 2 * (static_cast<std::ptrdiff_t>(r) * cols_ + k) + 1;
    const float* f1 = f0 + 2 * cols_;
    const float a = f0[0] + t * (f0[2] - f0[0]);
    const float b = f1[0] + t * (f1[2] - f1[0]);
    return a + w * (b - a);
  }

 private:
  void row_weight(double i, int& r, float& w) const {
    i = std::clamp(i, 0.0, rows_ - 1.001);
    r = static_cast<int>(i);
    w = static_cast<float>(i - r);
  }
  void col(double j, int& k, float& t) const {
    j = std::clamp(j, 0.0, cols_ - 1.001);
    k = static_cast<int>(j);
    t = static_cast<float>(j - k);
  }
  const float* base_;
  int rows_;
  int cols_;
};

/// Mean of the blurred reflectance (minus kOffset) along a straight piece of
/// path from (ja, ia) to (jb, ib), traversed at uniform speed. Pieces that
/// cross raster rows are cut into steps of at most 1/2 raster row, each
/// integrated along its mid row.
inline float segment_mean(const Lookup& lut, double ja, double ia, double jb, double ib) {
  const double di = ib - ia;
  const double dj = jb - ja;
  // ceil(|di| * 2) without a libm call; at least 1 step, at most 4096.
  const int n = std::clamp(static_cast<int>(std::abs(di) * 2.0 + 0.999999), 1, 4096);
  float sum = 0.0f;
  const double step_j = dj / n;
  const double step_i = di / n;
  for (int m = 0; m < n; ++m) {
    const double j0 = ja + m * step_j;
    const double j1 = j0 + step_j;
    const double im = ia + (m + 0.5) * step_i;
    if (std::abs(step_j) >= 1.0) {
      sum += lut.integral(j0, j1, im) / static_cast<float>(step_j);
    } else {
      sum += lut.sample(0.5 * (j0 + j1), im);
    }
  }
  return sum / static_cast<float>(n);
}

}  // namespace

void ExposureRenderer::render(const Ground& ground, const Trajectory& trajectory,
                              const core::CameraGeometry& camera, double camera_height_mm,
                              const std::vector<LightInterval>& light, cv::Mat& out) {
  if (light.empty()) throw std::invalid_argument("simulator: exposure without light");
  const CameraFrame cam{camera.mm_per_px,
                        (camera.height_px - 1) / 2.0,
                        (camera.width_px - 1) / 2.0,
                        camera.mount_yaw_deg * 3.14159265358979323846 / 180.0,
                        camera.width_px,
                        camera.height_px,
                        camera_height_mm};
  const double h = camera.mm_per_px / supersample_;

  // 1. Knots of every light interval.
  std::vector<PoseAt> poses;
  std::vector<std::size_t> begin;
  for (const LightInterval& iv : light) {
    begin.push_back(poses.size());
    const PoseAt a{iv.t0_s, trajectory.pose(iv.t0_s), trajectory.body(iv.t0_s)};
    const PoseAt b{iv.t1_s, trajectory.pose(iv.t1_s), trajectory.body(iv.t1_s)};
    poses.push_back(a);
    subdivide(trajectory, cam, a, b, kPathTolerancePx * camera.mm_per_px, 0, poses);
  }
  begin.push_back(poses.size());
  bool projective = false;
  for (const PoseAt& k : poses) {
    if (!(cam.height_mm + k.body.heave_mm > 0.05 * cam.height_mm))
      throw std::invalid_argument("simulator: body motion puts the camera on the ground (height " +
                                  std::to_string(cam.height_mm + k.body.heave_mm) + " mm)");
    projective = projective || !is_level(k.body);
  }

  // 2. Raster orientation: along the travel of the image centre, else the image rows.
  double cx0, cy0, cx1, cy1;
  pixel_world(cam, poses.front().pose, poses.front().body, cam.rc, cam.cc, cx0, cy0);
  pixel_world(cam, poses.back().pose, poses.back().body, cam.rc, cam.cc, cx1, cy1);
  RasterGrid grid;
  grid.spacing_mm = h;
  grid.spacing_u_mm = h;
  // Long blur in every light interval: the path integral smooths along the
  // motion anyway, so the raster along it may be at the pixel pitch.
  if (coarse_min_blur_px_ > 0.0) {
    double shortest = 1e300;
    for (std::size_t iv = 0; iv + 1 < begin.size(); ++iv) {
      double xa, ya, xb, yb;
      const PoseAt& a = poses[begin[iv]];
      const PoseAt& b = poses[begin[iv + 1] - 1];
      pixel_world(cam, a.pose, a.body, cam.rc, cam.cc, xa, ya);
      pixel_world(cam, b.pose, b.body, cam.rc, cam.cc, xb, yb);
      shortest = std::min(shortest, std::hypot(xb - xa, yb - ya) / camera.mm_per_px);
    }
    if (shortest >= coarse_min_blur_px_) grid.spacing_u_mm = camera.mm_per_px;
  }
  const double travel = std::hypot(cx1 - cx0, cy1 - cy0);
  if (travel > 2.0 * h) {
    grid.ux = (cx1 - cx0) / travel;
    grid.uy = (cy1 - cy0) / travel;
  } else {
    const double phi = poses.front().pose.yaw_rad + cam.mount_rad;
    grid.ux = -std::cos(phi);  // camera -x: the direction of increasing image row
    grid.uy = -std::sin(phi);
  }

  // 3. Raster bounds over all knots' image corners (world-aligned integer
  // origin; a tilted view is a convex quadrilateral, so its corners bound it too).
  double jmin = 1e300, jmax = -1e300, imin = 1e300, imax = -1e300;
  for (const PoseAt& k : poses) {
    for (const double r : {-0.5, cam.height - 0.5}) {
      for (const double c : {-0.5, cam.width - 0.5}) {
        double x, y, j, i;
        if (!is_level(k.body)) {
          const ViewMap m = view_map(cam, k.pose, k.body);
          // The corner's ray must meet the ground in front of the camera.
          if (!(m.w00 + r * m.wr + c * m.wc > 0.1))
            throw std::invalid_argument("simulator: body tilt makes the camera see the horizon");
        }
        pixel_world(cam, k.pose, k.body, r, c, x, y);
        grid.to_raster(x, y, j, i);
        jmin = std::min(jmin, j);
        jmax = std::max(jmax, j);
        imin = std::min(imin, i);
        imax = std::max(imax, i);
      }
    }
  }
  grid.u0 = std::floor(jmin) - kMargin;
  grid.v0 = std::floor(imin) - kMargin;
  grid.cols = static_cast<int>(std::ceil(jmax) - grid.u0) + kMargin + 1;
  grid.rows = static_cast<int>(std::ceil(imax) - grid.v0) + kMargin + 1;
  if (static_cast<double>(grid.cols) * grid.rows > 4.0e8)
    throw std::invalid_argument("simulator: motion during the exposure too long to render");

  // 4. Knots as maps pixel -> raster coordinates: affine for a level body,
  // projective for a tilted one.
  knots_.clear();
  for (const PoseAt& pk : poses) {
    if (projective) {
      knots_.push_back(projective_knot(pk.t_s, view_map(cam, pk.pose, pk.body), grid));
      continue;
    }
    const Pose& p = pk.pose;
    double x0, y0, xr, yr, xc, yc;
    pixel_world(cam, p, pk.body, 0.0, 0.0, x0, y0);
    pixel_world(cam, p, pk.body, 1.0, 0.0, xr, yr);
    pixel_world(cam, p, pk.body, 0.0, 1.0, xc, yc);
    Knot k{};
    k.t_s = pk.t_s;
    grid.to_raster(x0, y0, k.j00, k.i00);
    double j, i;
    grid.to_raster(xr, yr, j, i);
    k.jr = j - k.j00;
    k.ir = i - k.i00;
    grid.to_raster(xc, yc, j, i);
    k.jc = j - k.j00;
    k.ic = i - k.i00;
    knots_.push_back(k);
  }
  interval_begin_ = begin;

  // Scale of the view at the middle knot against the nominal height (1 exactly without body motion).
  const double psf_scale = level_scale(cam, poses[poses.size() / 2].body);

  // 5. Texture, PSF and prefix sums, in parallel row strips.
  const int rows = grid.rows;
  const int cols = grid.cols;
  const auto total = static_cast<std::size_t>(rows) * static_cast<std::size_t>(cols);
  reflectance_.resize(total);
  cells_.resize(2 * total);
  const int strips = std::clamp(rows / 48, 1, 256);
  auto strip_rows = [&](int s, int& r0, int& r1) {
    r0 = static_cast<int>(static_cast<long long>(rows) * s / strips);
    r1 = static_cast<int>(static_cast<long long>(rows) * (s + 1) / strips);
  };
  using Clock = std::chrono::steady_clock;
  auto ms_since = [](Clock::time_point t) {
    return std::chrono::duration<double, std::milli>(Clock::now() - t).count();
  };
  auto t_stage = Clock::now();
  // The raster of the previous frame is reused when it is the same raster
  // (standing car): its samples are a function of their world position only.
  const bool same_raster = ground_id_ == &ground && grid.u0 == last_grid_.u0 &&
                           grid.v0 == last_grid_.v0 && grid.ux == last_grid_.ux &&
                           grid.uy == last_grid_.uy && grid.spacing_mm == last_grid_.spacing_mm &&
                           grid.spacing_u_mm == last_grid_.spacing_u_mm &&
                           grid.rows == last_grid_.rows && grid.cols == last_grid_.cols &&
                           psf_scale == last_psf_scale_;
  stats_.texture_ms = 0.0;
  if (!same_raster) {
    for_strips(parallel_, cv::Range(0, strips), [&](const cv::Range& range) {
      for (int s = range.start; s < range.end; ++s) {
        int r0, r1;
        strip_rows(s, r0, r1);
        float* rows_out = reflectance_.data() + static_cast<std::ptrdiff_t>(r0) * cols;
        ground.render_rows(grid, r0, r1, rows_out);
      }
    });

    stats_.texture_ms = ms_since(t_stage);
    t_stage = Clock::now();
    // Gaussian PSF taps across (rows) and along (columns) the raster.
    auto taps = [](double sigma) {
      std::array<float, 2 * kPsfRadius + 1> t{};
      double sum = 0.0;
      for (int k = -kPsfRadius; k <= kPsfRadius; ++k) sum += std::exp(-0.5 * k * k / (sigma * sigma));
      for (int k = -kPsfRadius; k <= kPsfRadius; ++k)
        t[static_cast<std::size_t>(k + kPsfRadius)] =
            static_cast<float>(std::exp(-0.5 * k * k / (sigma * sigma)) / sum);
      return t;
    };
    // The PSF is fixed in the image: on the ground it grows with the height.
    const auto w = taps(kPsfSigmaPx * camera.mm_per_px * psf_scale / grid.spacing_mm);
    const auto wu = taps(kPsfSigmaPx * camera.mm_per_px * psf_scale / grid.spacing_u_mm);
    // One raster row r blurred by the PSF into dst's f slots (vert: cols floats of scratch).
    auto psf_row = [&](int r, float* vert, float* dst) {
      // Vertical pass (rows clamped at the raster edge; the margin keeps it out of view).
      std::fill(vert, vert + cols, 0.0f);
      for (int k = -kPsfRadius; k <= kPsfRadius; ++k) {
        const int rr = std::clamp(r + k, 0, rows - 1);
        const float wk = w[static_cast<std::size_t>(k + kPsfRadius)];
        const float* src = reflectance_.data() + static_cast<std::ptrdiff_t>(rr) * cols;
        for (int c = 0; c < cols; ++c) vert[c] += wk * src[c];
      }
      // Horizontal pass.
      for (int c = 0; c < cols; ++c) {
        float acc = 0.0f;
        if (c >= kPsfRadius && c < cols - kPsfRadius) {
          for (int k = -kPsfRadius; k <= kPsfRadius; ++k)
            acc += wu[static_cast<std::size_t>(k + kPsfRadius)] * vert[c + k];
        } else {
          for (int k = -kPsfRadius; k <= kPsfRadius; ++k)
            acc += wu[static_cast<std::size_t>(k + kPsfRadius)] * vert[std::clamp(c + k, 0, cols - 1)];
        }
        dst[2 * c + 1] = acc - kOffset;
      }
    };
    for_strips(parallel_, cv::Range(0, strips), [&](const cv::Range& range) {
      std::vector<float> vert(static_cast<std::size_t>(cols));
      for (int s = range.start; s < range.end; ++s) {
        int r0, r1;
        strip_rows(s, r0, r1);
        for (int r = r0; r < r1; ++r) {
          float* dst = cells_.data() + 2 * static_cast<std::ptrdiff_t>(r) * cols;
          if (ground_has_psf_) {
            // The ground already holds the PSF (a pre-blurred tile): the samples as they are.
            const float* src = reflectance_.data() + static_cast<std::ptrdiff_t>(r) * cols;
            for (int c = 0; c < cols; ++c) dst[2 * c + 1] = src[c] - kOffset;
          } else {
            psf_row(r, vert.data(), dst);
          }
          // Prefix integral of the linear interpolant.
          double run = 0.0;
          dst[0] = 0.0f;
          for (int c = 1; c < cols; ++c) {
            run += 0.5 * (static_cast<double>(dst[2 * c - 1]) + static_cast<double>(dst[2 * c + 1]));
            dst[2 * c] = static_cast<float>(run);
          }
        }
      }
    });
  }
  ground_id_ = &ground;
  last_grid_ = grid;
  last_psf_scale_ = psf_scale;
  stats_.psf_ms = ms_since(t_stage);
  t_stage = Clock::now();
  // 6. Path integrals per pixel.
  out.create(camera.height_px, camera.width_px, CV_32FC1);
  if (supersample_ == 1.0 && !projective &&
      integrate_translating(cells_.data(), rows, cols, knots_, interval_begin_, kOffset, parallel_, box_, out)) {
    stats_.integrate_ms = ms_since(t_stage);
    stats_.raster_rows = rows;
    stats_.raster_cols = cols;
    stats_.knots = knots_.size();
    stats_.box_filtered = true;
    return;
  }
  double lit = 0.0;
  for (const LightInterval& iv : light) lit += iv.t1_s - iv.t0_s;
  const Lookup lut(cells_.data(), rows, cols);
  const std::size_t n_intervals = light.size();
  const int height = camera.height_px;
  const int width = camera.width_px;
  // Raster point of pixel (r, c) at knot k: affine, or divided by the
  // knot's w for a tilted body (instantiated separately, so the level case
  // runs the same instructions as before body motion existed).
  const auto integrate = [&](auto projective_tag) {
    constexpr bool kProjective = decltype(projective_tag)::value;
    const auto at = [](const Knot& k, int r, int c, double& j, double& i) {
      j = k.j00 + r * k.jr + c * k.jc;
      i = k.i00 + r * k.ir + c * k.ic;
      if constexpr (kProjective) {
        const double inv_w = 1.0 / (k.w00 + r * k.wr + c * k.wc);
        j *= inv_w;
        i *= inv_w;
      }
    };
    for_strips(parallel_, cv::Range(0, height), [&](const cv::Range& range) {
      for (int r = range.start; r < range.end; ++r) {
        float* dst = out.ptr<float>(r);
        for (int c = 0; c < width; ++c) {
          double acc = 0.0;
          for (std::size_t iv = 0; iv < n_intervals; ++iv) {
            const std::size_t k0 = interval_begin_[iv];
            const std::size_t k1 = interval_begin_[iv + 1];
            double ja, ia;
            at(knots_[k0], r, c, ja, ia);
            for (std::size_t k = k0 + 1; k < k1; ++k) {
              const Knot& kb = knots_[k];
              double jb, ib;
              at(kb, r, c, jb, ib);
              acc += (kb.t_s - knots_[k - 1].t_s) * static_cast<double>(segment_mean(lut, ja, ia, jb, ib));
              ja = jb;
              ia = ib;
            }
          }
          dst[c] = kOffset + static_cast<float>(acc / lit);
        }
      }
    }, 16);
  };
  if (projective) {
    integrate(std::true_type{});
  } else {
    integrate(std::false_type{});
  }

  stats_.integrate_ms = ms_since(t_stage);
  stats_.raster_rows = rows;
  stats_.raster_cols = cols;
  stats_.knots = knots_.size();
  stats_.box_filtered = false;
}

}  // namespace gvs::drivers::sim
