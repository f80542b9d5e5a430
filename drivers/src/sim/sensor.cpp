#include "sensor.hpp"

#include <algorithm>
#include <cmath>

#include <opencv2/core/utility.hpp>

#include "hash.hpp"
#include "sensor_pixel.hpp"

namespace gvs::drivers::sim {

Sensor::Sensor(const SensorModel& model, const core::CameraGeometry& camera,
               std::uint64_t sensor_seed)
    : model_(model) {
  const int h = camera.height_px;
  const int w = camera.width_px;
  response_.create(h, w, CV_32FC1);
  offset_.create(h, w, CV_32FC1);
  // LED ring falloff: V = (1 + (rho/rho0)^2)^-2, rho0 chosen so that the
  // corners get (1 - corner_falloff) of the centre's light.
  const double rc = (h - 1) / 2.0;
  const double cc = (w - 1) / 2.0;
  const double corner2 = rc * rc + cc * cc;
  const double keep = std::clamp(1.0 - model.corner_falloff, 0.05, 1.0);
  const double x_corner = 1.0 / std::sqrt(keep) - 1.0;  // (rho_c/rho0)^2
  detail::Rng fpn(detail::mix64(sensor_seed ^ 0xF1ED0A77E2ULL));
  std::vector<float> column(static_cast<std::size_t>(w));
  for (auto& v : column)
    v = model.fixed_pattern_noise ? static_cast<float>(model.column_dsnu_dn) * fpn.normal() : 0.0f;
  for (int r = 0; r < h; ++r) {
    auto* resp = response_.ptr<float>(r);
    auto* off = offset_.ptr<float>(r);
    for (int c = 0; c < w; ++c) {
      const double rho2 = ((r - rc) * (r - rc) + (c - cc) * (c - cc)) / corner2 * x_corner;
      const double falloff = model.light_falloff ? 1.0 / ((1.0 + rho2) * (1.0 + rho2)) : 1.0;
      double prnu = 1.0;
      double dsnu = 0.0;
      if (model.fixed_pattern_noise) {
        prnu += model.prnu * static_cast<double>(fpn.normal());
        dsnu = model.dsnu_dn * static_cast<double>(fpn.normal());
      }
      resp[c] = static_cast<float>(falloff * prnu);
      off[c] = static_cast<float>(model.black_level_dn + dsnu) + column[static_cast<std::size_t>(c)];
    }
  }
}

void Sensor::electrons(const cv::Mat& reflectance, double e_per_reflectance, cv::Mat& out) const {
  cv::multiply(reflectance, response_, out, e_per_reflectance, CV_32F);
}

void Sensor::expose(const cv::Mat& reflectance, double e_per_reflectance, double gain_dn_per_e,
                    std::uint64_t noise_seed, cv::Mat& gray) const {
  gray.create(reflectance.rows, reflectance.cols, CV_8UC1);
  const PixelModel m = pixel_model(e_per_reflectance, gain_dn_per_e);
  cv::parallel_for_(cv::Range(0, reflectance.rows), [&](const cv::Range& range) {
    for (int r = range.start; r < range.end; ++r) {
      detail::Rng rng(detail::hash_cell(noise_seed, 7, r, 0));
      expose_row(m, reflectance.ptr<float>(r), response_.ptr<float>(r), offset_.ptr<float>(r),
                 gray.ptr<std::uint8_t>(r), reflectance.cols, rng);
    }
  }, 8);
}

PixelModel Sensor::pixel_model(double e_per_reflectance, double gain_dn_per_e) const {
  return {static_cast<float>(e_per_reflectance), static_cast<float>(gain_dn_per_e),
          static_cast<float>(model_.full_well_e), static_cast<float>(model_.read_noise_e * model_.read_noise_e),
          model_.shot_and_read_noise};
}

}  // namespace gvs::drivers::sim
