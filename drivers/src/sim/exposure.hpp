// Integrates the ground texture over the real motion of each pixel's line of
// sight while light reaches the sensor (docs/simulator.md, "Exposure").
#pragma once

#include <cstddef>
#include <vector>

#include <opencv2/core/mat.hpp>

#include "ground.hpp"
#include "gvs/drivers/sim/render_stats.hpp"
#include "gvs/drivers/sim/scenario.hpp"
#include "gvs/core/frame.hpp"

namespace gvs::drivers::sim {

/// A time interval during which light reaches the sensor (absolute seconds).
struct LightInterval {
  double t0_s = 0.0;
  double t1_s = 0.0;
};

using ExposureStats = RenderStats;

class ExposureRenderer {
 public:
  /// Raster spacing: half a sensor pixel (2x supersampling).
  static constexpr double kSupersample = 2.0;
  /// Isotropic blur of pixel footprint + optics, sigma in sensor pixels.
  static constexpr double kPsfSigmaPx = 0.5;
  /// Largest allowed deviation of a pixel's path from its straight chord, px.
  static constexpr double kPathTolerancePx = 0.05;

  /// Writes into `out` (CV_32FC1, height x width) the reflectance of `ground`
  /// each pixel saw, averaged over the light intervals (time-weighted).
  /// `camera.mm_per_px` holds at `camera_height_mm`, the nominal height; the
  /// trajectory's body pose moves and tilts the camera from there
  /// (camera_view.hpp). Throws std::invalid_argument when the body pose puts
  /// the camera on the ground or its view up to the horizon.
  void render(const Ground& ground, const Trajectory& trajectory, const core::CameraGeometry& camera,
              double camera_height_mm, const std::vector<LightInterval>& light, cv::Mat& out);

  [[nodiscard]] const ExposureStats& stats() const { return stats_; }

  /// Blur (px, shortest light interval) from which the raster along the
  /// motion uses the pixel pitch instead of half of it; <= 0: never.
  void set_coarse_min_blur_px(double px) { coarse_min_blur_px_ = px; }

  /// Live fast render (docs/simulator.md, "Live source"): the raster at the
  /// pixel pitch s in both axes instead of s/2 across the motion; when
  /// `ground_has_psf`, no PSF pass (the ground already holds it: a tile
  /// blurred once); path integrals by box filters where the view only
  /// translates (integrate_translating); everything on the calling thread.
  /// Off (the default): the exact render of datasets, over both cores.
  void set_live_fast(bool on, bool ground_has_psf) {
    supersample_ = on ? 1.0 : kSupersample;
    ground_has_psf_ = on && ground_has_psf;
    parallel_ = !on;
  }
  [[nodiscard]] bool parallel() const { return parallel_; }

  /// Raster coordinates of pixel (r, c) at one instant: j = j00 + r jr + c jc,
  /// same for i; for a tilted body both divided by w = w00 + r wr + c wc
  /// (a homography; level: w = 1 and unused).
  struct Knot {
    double t_s;
    double j00, jr, jc;
    double i00, ir, ic;
    double w00 = 1.0, wr = 0.0, wc = 0.0;
  };

 private:
  std::vector<float> reflectance_;
  /// Per raster sample, interleaved: s = integral of the (linearly
  /// interpolated) row from column 0 to here, f = blurred reflectance - offset.
  std::vector<float> cells_;
  std::vector<Knot> knots_;
  std::vector<std::size_t> interval_begin_;  ///< first knot of each interval (+ end)
  ExposureStats stats_;
  double coarse_min_blur_px_ = 32.0;
  std::vector<float> box_;  ///< live fast path: one piece's box-filtered raster
  double supersample_ = kSupersample;  ///< raster spacing s / supersample_ (across the motion)
  bool ground_has_psf_ = false;        ///< skip the PSF pass (the ground is pre-blurred)
  bool parallel_ = true;               ///< cv::parallel_for_ (else the calling thread only)
  const Ground* ground_id_ = nullptr;  ///< ground and grid of cells_
  RasterGrid last_grid_;
  double last_psf_scale_ = 1.0;  ///< the PSF of cells_ (height / nominal)
};

/// The live fast render's path integrals (exposure_translate.cpp): when every
/// piece of path between `knots` only translates the view (its path vector
/// varies by at most 0.05 raster px over the image) and crosses at most half
/// a raster row, writes into `out` (CV_32FC1, already image-sized) offset +
/// the time-weighted mean of the box-filtered raster (`cells`: prefix sums
/// and samples, interleaved) sampled bilinearly at each pixel, and returns
/// true; otherwise returns false and leaves `out` alone. `parallel`: over
/// both cores (else on the calling thread).
bool integrate_translating(const float* cells, int rows, int cols,
                           const std::vector<ExposureRenderer::Knot>& knots,
                           const std::vector<std::size_t>& interval_begin, float offset, bool parallel,
                           std::vector<float>& box, cv::Mat& out);

}  // namespace gvs::drivers::sim
