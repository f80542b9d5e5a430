// Laser dots in a simulated frame. See laser_dots.hpp and docs/simulator.md,
// "Laser dots".
#include "laser_dots.hpp"

#include <algorithm>
#include <cmath>

#include "camera_view.hpp"
#include "hash.hpp"

namespace gvs::drivers::sim {
namespace {

constexpr double kPsfSigmaPx = 0.5;  // optics + pixel footprint, as the asphalt's (docs/simulator.md)
constexpr int kSubPixel = 2;         // speckle sampled 2 x 2 per pixel (the pixel integrates it)
constexpr double kSpeckleCellMm = 0.05;

/// The ground's normal in head axes: R^T e_z in vehicle axes (R = Ry(pitch)
/// Rx(roll), camera_view.hpp), rotated by the camera's mount yaw.
core::Vec3 ground_normal_head(const core::CameraGeometry& camera, const BodyPose& b) {
  const double th = core::deg_to_rad(b.pitch_deg);
  const double ph = core::deg_to_rad(b.roll_deg);
  const double nx = -std::sin(th);
  const double ny = std::cos(th) * std::sin(ph);
  const double nz = std::cos(th) * std::cos(ph);
  const double m = core::deg_to_rad(camera.mount_yaw_deg);
  return {std::cos(m) * nx + std::sin(m) * ny, -std::sin(m) * nx + std::cos(m) * ny, nz};
}

/// Speckle intensity (mean 1) of the ground cell under world point (x, y)
/// mm: the mean of `grains` exponential variates (fully developed speckle,
/// Goodman), i.e. a gamma variate of contrast 1 / sqrt(grains).
double speckle(std::uint64_t seed, std::size_t beam, double x_mm, double y_mm, double cell_mm, int grains) {
  const auto ix = static_cast<std::int64_t>(std::floor(x_mm / cell_mm));
  const auto iy = static_cast<std::int64_t>(std::floor(y_mm / cell_mm));
  std::uint64_t h = detail::hash_cell(seed, 0x1A5E0 + beam, ix, iy);
  double sum = 0.0;
  for (int g = 0; g < grains; ++g) {
    h = detail::mix64(h + 0x9E3779B97F4A7C15ULL);
    sum -= std::log((static_cast<double>(h >> 11) + 0.5) * 0x1.0p-53);
  }
  return sum / grains;
}

}  // namespace

bool laser_spot(const core::CameraGeometry& camera, double nominal_height_mm, const core::LaserBeam& beam,
                const BodyPose& b, core::Vec3& ground_mm, double& row, double& col) {
  // Ground plane in head axes: n . (p + (0, 0, H)) = 0 (the vehicle's z axis
  // meets it H below the optical centre). Beam: p = O + t u.
  const double height_mm = nominal_height_mm + b.heave_mm;
  const core::Vec3 n = ground_normal_head(camera, b);
  const core::Vec3 o = beam.origin_mm();
  const core::Vec3 u = beam.direction();
  const double nu = core::dot(n, u);
  if (!(nu < -1e-6)) return false;
  const double t = -core::dot(n, o + core::Vec3{0.0, 0.0, height_mm}) / nu;
  if (!(t > 0.0)) return false;
  ground_mm = o + t * u;
  if (!(ground_mm.z < -1e-3)) return false;
  core::head_to_pixel(camera, nominal_height_mm, ground_mm, row, col);
  return true;
}

void add_laser_dots(const core::LaserGeometry& lasers, const LaserLight& light, const Trajectory& trajectory,
                    const core::CameraGeometry& camera, double nominal_height_mm,
                    const std::vector<LightInterval>& intervals, std::uint64_t seed, cv::Mat& reflectance,
                    cv::Mat& scratch) {
  if (!lasers.enabled() || intervals.empty()) return;
  CV_Assert(reflectance.type() == CV_32FC1 && reflectance.rows == camera.height_px &&
            reflectance.cols == camera.width_px);
  scratch.create(reflectance.size(), CV_32FC1);
  scratch.setTo(0.0);
  const CameraFrame cam{camera.mm_per_px,         (camera.height_px - 1) / 2.0,
                        (camera.width_px - 1) / 2.0, core::deg_to_rad(camera.mount_yaw_deg),
                        camera.width_px,          camera.height_px,
                        nominal_height_mm};
  double lit_s = 0.0;
  for (const LightInterval& iv : intervals) lit_s += iv.t1_s - iv.t0_s;
  if (!(lit_s > 0.0)) return;
  // Speckle: grains of lambda / (2 NA) on the ground, drawn per cell of
  // kSpeckleCellMm as the mean of the grains the cell holds.
  const int grains = std::max(1, static_cast<int>(std::lround(std::pow(kSpeckleCellMm / light.speckle_grain_mm, 2))));
  int r_lo = camera.height_px, r_hi = -1, c_lo = camera.width_px, c_hi = -1;

  for (const LightInterval& iv : intervals) {
    // Instants every 50 us at most: a kerb strike (375 mm/s) moves a dot
    // 0.2 px between them.
    const double dur_s = iv.t1_s - iv.t0_s;
    const int n = std::clamp(static_cast<int>(std::ceil(dur_s / 50e-6)), 1, 200);
    const double weight = light.peak_relative * (dur_s / n) / lit_s;
    for (int i = 0; i < n; ++i) {
      const double t = iv.t0_s + (i + 0.5) * dur_s / n;
      const Pose pose = trajectory.pose(t);
      const BodyPose body = trajectory.body(t);
      const ViewMap view = view_map(cam, pose, body);  // pixel -> world ground point, for the speckle
      const double height_mm = nominal_height_mm + body.heave_mm;
      // Spot size in pixels at this height, plus the optics' blur; the
      // oblique beam stretches it by 1 / cos(tilt) along its track.
      const double sigma_px = lasers.spot_sigma_mm / (camera.mm_per_px * height_mm / nominal_height_mm);
      for (std::size_t k = 0; k < lasers.count; ++k) {
        const core::LaserBeam& beam = lasers.beams[k];
        core::Vec3 g;
        double row = 0.0, col = 0.0;
        if (!laser_spot(camera, nominal_height_mm, beam, body, g, row, col)) continue;
        const double cos_tilt = std::max(0.1, std::cos(core::deg_to_rad(beam.tilt_deg)));
        const double s_across = std::hypot(sigma_px, kPsfSigmaPx);
        const double s_along = std::hypot(sigma_px / cos_tilt, kPsfSigmaPx);
        // Track direction in the image: head x is -row, head y is -col.
        const core::Vec3 u = beam.direction();
        const double norm = std::hypot(u.x, u.y);
        const double er = norm > 1e-9 ? -u.x / norm : 1.0;
        const double ec = norm > 1e-9 ? -u.y / norm : 0.0;
        const int reach = static_cast<int>(std::ceil(4.0 * s_along)) + 1;
        const int r0 = std::max(0, static_cast<int>(std::floor(row)) - reach);
        const int r1 = std::min(camera.height_px - 1, static_cast<int>(std::floor(row)) + reach);
        const int c0 = std::max(0, static_cast<int>(std::floor(col)) - reach);
        const int c1 = std::min(camera.width_px - 1, static_cast<int>(std::floor(col)) + reach);
        for (int r = r0; r <= r1; ++r) {
          auto* dst = scratch.ptr<float>(r);
          for (int c = c0; c <= c1; ++c) {
            const double dr = r - row, dc = c - col;
            const double along = dr * er + dc * ec;
            const double across = -dr * ec + dc * er;
            const double q = along * along / (s_along * s_along) + across * across / (s_across * s_across);
            if (q > 16.0) continue;
            double sp = 0.0;
            for (int i2 = 0; i2 < kSubPixel; ++i2) {
              for (int j2 = 0; j2 < kSubPixel; ++j2) {
                double x = 0.0, y = 0.0;
                view.world(r + (i2 + 0.5) / kSubPixel - 0.5, c + (j2 + 0.5) / kSubPixel - 0.5, x, y);
                sp += speckle(seed, k, x, y, kSpeckleCellMm, grains);
              }
            }
            dst[c] += static_cast<float>(weight * std::exp(-0.5 * q) * sp / (kSubPixel * kSubPixel));
          }
        }
        r_lo = std::min(r_lo, r0);
        r_hi = std::max(r_hi, r1);
        c_lo = std::min(c_lo, c0);
        c_hi = std::max(c_hi, c1);
      }
    }
  }
  // R += R * dots: the spot lights the asphalt under it, dark stones stay darker.
  for (int r = r_lo; r <= r_hi; ++r) {
    auto* dst = reflectance.ptr<float>(r);
    const auto* add = scratch.ptr<float>(r);
    for (int c = c_lo; c <= c_hi; ++c) dst[c] += dst[c] * add[c];
  }
}

}  // namespace gvs::drivers::sim
