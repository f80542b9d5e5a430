// The camera sensor: LED-ring falloff, photon shot noise, read noise, fixed
// pattern noise (PRNU, DSNU), gain, 8-bit quantisation with clipping.
#pragma once

#include "sensor_pixel.hpp"

#include <cstdint>

#include <opencv2/core/mat.hpp>

#include "gvs/drivers/sim/sensor_model.hpp"
#include "gvs/core/frame.hpp"

namespace gvs::drivers::sim {

class Sensor {
 public:
  Sensor(const SensorModel& model, const core::CameraGeometry& camera, std::uint64_t sensor_seed);

  /// Noise-free signal in electrons (before full-well clipping) for a
  /// reflectance image and `e_per_reflectance` electrons per unit reflectance
  /// at the image centre.
  void electrons(const cv::Mat& reflectance, double e_per_reflectance, cv::Mat& out) const;

  /// The frame: shot + read noise on the electrons, full well, gain, FPN offset,
  /// rounding and clipping to 8 bits.
  void expose(const cv::Mat& reflectance, double e_per_reflectance, double gain_dn_per_e,
              std::uint64_t noise_seed, cv::Mat& gray) const;

  /// The live fast render's frame (sensor_live.cpp): the same model on the
  /// calling thread, with the Gaussian draws (shot noise above 30 e-, read
  /// noise) taken from a 4096-entry table of normal quantiles instead of
  /// Box-Muller: the same noise level and distribution up to 3.67 sigma
  /// (docs/simulator.md, "Live source"); dim pixels keep the exact Poisson.
  void expose_live(const cv::Mat& reflectance, double e_per_reflectance, double gain_dn_per_e,
                   std::uint64_t noise_seed, cv::Mat& gray) const;

  [[nodiscard]] const SensorModel& model() const { return model_; }

 private:
  [[nodiscard]] PixelModel pixel_model(double e_per_reflectance, double gain_dn_per_e) const;
  SensorModel model_;
  cv::Mat response_;  ///< light falloff x PRNU, CV_32F
  cv::Mat offset_;    ///< black level + DSNU, DN, CV_32F
};

}  // namespace gvs::drivers::sim
