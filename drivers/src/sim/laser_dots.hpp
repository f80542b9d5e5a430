// The laser dots in a simulated frame (docs/simulator.md, "Laser dots"):
// each beam of core::LaserGeometry meets the ground plane of the body's
// pose at every instant the light is on, and lights a Gaussian spot with
// laser speckle, times the asphalt's reflectance under it.
#pragma once

#include <cstdint>
#include <vector>

#include <opencv2/core/mat.hpp>

#include "gvs/core/frame.hpp"
#include "gvs/core/laser_geometry.hpp"
#include "gvs/drivers/sim/scenario.hpp"
#include "exposure.hpp"

namespace gvs::drivers::sim {

/// Where beam `beam` meets the ground at body pose `b` (head axes, mm), and
/// the pixel it is seen at. False when the beam does not reach the ground
/// below the camera.
bool laser_spot(const core::CameraGeometry& camera, double nominal_height_mm, const core::LaserBeam& beam,
                const BodyPose& b, core::Vec3& ground_mm, double& row, double& col);

struct LaserLight {
  /// Irradiance at the spot's centre over the LED ring's, both on the same
  /// ground (the laser is switched and overdriven with the LED strobe, so
  /// the ratio holds in every exposure mode).
  double peak_relative = 8.0;
  /// Size of a speckle grain on the ground, mm: lambda / (2 NA), 0.65 um
  /// over twice the lens's object-side NA of 0.012 (a 1.4 mm pupil 60 mm
  /// away): 0.027 mm, a quarter of a pixel.
  double speckle_grain_mm = 0.027;
};

/// Adds the dots to `reflectance` (CV_32FC1, the exposure's time-averaged
/// reflectance): R += R * sum over the lit instants of peak * spot * speckle.
void add_laser_dots(const core::LaserGeometry& lasers, const LaserLight& light, const Trajectory& trajectory,
                    const core::CameraGeometry& camera, double nominal_height_mm,
                    const std::vector<LightInterval>& intervals, std::uint64_t seed, cv::Mat& reflectance,
                    cv::Mat& scratch);

}  // namespace gvs::drivers::sim
