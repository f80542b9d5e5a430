// gvs calibrate height's fit (gvs/dsp/laser_calibration.hpp): simulated
// frames of the head on spacer blocks give back the beams they were
// rendered with, starting from the design's (different) geometry.
#include <gtest/gtest.h>

#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

#include "gvs/core/laser_geometry.hpp"
#include "gvs/drivers/png_file.hpp"
#include "gvs/drivers/simulator.hpp"
#include "gvs/dsp/laser_calibration.hpp"
#include "gvs/dsp/laser_dots.hpp"

namespace gvs::dsp {
namespace {

constexpr double kNominalMm = 60.0;

/// A matte calibration plate: a uniform light grey photograph (asphalt has
/// bright grains as sharp as the dots; the spacer blocks stand on a plate).
std::string plate_png() {
  const std::filesystem::path file =
      std::filesystem::temp_directory_path() / ("gvs-laser-plate-" + std::to_string(::getpid()) + ".png");
  const std::string error = drivers::write_png(file.string(), cv::Mat(512, 512, CV_8UC1, cv::Scalar(150)));
  if (!error.empty()) throw std::runtime_error(error);
  return file.string();
}

TEST(LaserCalibration, SpacerFramesGiveBackTheBeams) {
  drivers::SimulatorConfig c;
  c.seed = 11;
  const std::string plate = plate_png();
  c.ground = "photo:" + plate + ":0.2";
  const core::LaserGeometry design = core::design_laser_geometry(c.camera, kNominalMm);
  // The head as built: every beam a little off the drawing.
  core::LaserGeometry built = design;
  built.beams[0].tilt_deg = 43.2;
  built.beams[0].azimuth_deg = -88.5;
  built.beams[1].x_mm += 0.8;
  built.beams[1].tilt_deg = 46.1;
  built.beams[2].y_mm -= 1.1;
  built.beams[2].azimuth_deg = 178.0;
  c.lasers = built;
  std::vector<HeightObservation> observations;
  const double sigma_px = std::hypot(built.spot_sigma_mm / c.camera.mm_per_px, 0.5) * 1.2;
  for (const double h : {50.0, 55.0, 60.0, 65.0, 70.0}) {
    auto s = drivers::sim::constant_motion_scenario(0.0, 0.0);
    s.body = [h](double) { return drivers::sim::BodyPose{h - kNominalMm, 0.0, 0.0}; };
    drivers::Simulator sim(c, s);
    drivers::SimFrame f;
    core::ExposurePlan plan;
    plan.exposure_us = 1000.0;
    for (int i = 0; i < 3; ++i) {
      sim.render(i, plan, f);
      observations.push_back({h, find_bright_spots(f.gray, sigma_px, 5)});
    }
  }
  const auto fit = fit_laser_geometry(observations, c.camera, kNominalMm, design, -20.0);
  ASSERT_TRUE(fit.has_value());
  EXPECT_EQ(fit->heights_used, observations.size());
  EXPECT_LT(fit->rms_residual_mm, 0.05);
  for (std::size_t k = 0; k < 3; ++k) {
    const core::LaserBeam& got = fit->lasers.beams[k];
    const core::LaserBeam& want = built.beams[k];
    EXPECT_NEAR(got.tilt_deg, want.tilt_deg, 0.2) << "beam " << k;
    EXPECT_NEAR(got.azimuth_deg, want.azimuth_deg, 0.5) << "beam " << k;
    // The exit point at z = -20 mm: where the built beam passes there.
    const double t = (want.z_mm - -20.0) / -want.direction().z;
    EXPECT_NEAR(got.x_mm, want.x_mm + t * want.direction().x, 0.3) << "beam " << k;
    EXPECT_NEAR(got.y_mm, want.y_mm + t * want.direction().y, 0.3) << "beam " << k;
  }
  std::filesystem::remove(plate);
  // On asphalt, the fitted geometry measures a height it was not fitted at; the design's does not.
  c.ground = "procedural";
  auto s = drivers::sim::constant_motion_scenario(3.0, 0.0);
  s.body = [](double) { return drivers::sim::BodyPose{2.5, 0.0, 0.0}; };
  drivers::Simulator sim(c, s);
  drivers::SimFrame f;
  core::ExposurePlan plan;
  plan.exposure_us = 1000.0;
  LaserDotFinder fitted(c.camera, kNominalMm, fit->lasers);
  LaserDotFinder drawn(c.camera, kNominalMm, design);
  int measured = 0;
  for (int i = 5; i < 10; ++i) {
    sim.render(i, plan, f);
    const LaserDotResult res = fitted.find(f.gray);
    if (res.ride.has_height) {
      ++measured;
      EXPECT_NEAR(res.ride.height_mm, 62.5, 0.1) << "frame " << i;
    }
    const LaserDotResult wrong = drawn.find(f.gray);
    EXPECT_TRUE(!wrong.ride.has_height || std::abs(wrong.ride.height_mm - 62.5) > 0.3) << "frame " << i;
  }
  EXPECT_GE(measured, 3);
}

}  // namespace
}  // namespace gvs::dsp
