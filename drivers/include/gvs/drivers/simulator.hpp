// The simulated ground camera: procedural asphalt (or a seamless photograph)
// seen by a top-down camera on a car driven by a scenario. It is the ground truth behind every figure
// gvs publishes (docs/simulator.md).
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <opencv2/core/mat.hpp>

#include "gvs/drivers/dataset.hpp"
#include "gvs/drivers/sim/render_stats.hpp"
#include "gvs/drivers/sim/scenario.hpp"
#include "gvs/drivers/sim/sensor_model.hpp"
#include "gvs/core/frame.hpp"
#include "gvs/core/laser_geometry.hpp"

namespace gvs::drivers {

/// Scene brightness: `normal` aims at a mean grey of about 110; `under` at
/// about 10; `over` saturates about 15 % of the pixels.
enum class LightLevel { normal, under, over };

struct SimulatorConfig {
  std::string scenario = "sine";
  double seconds = 0.0;  ///< 0: the scenario's own length
  std::uint64_t seed = 1;
  double fps = 60.0;
  double exposure_us = 3000.0;  ///< continuous exposure unless a plan is set
  LightLevel light = LightLevel::normal;
  core::CameraGeometry camera;  ///< 512x384 px, 0.1 mm/px, mount yaw 0
  /// Nominal height of the camera's optical centre above the ground, where
  /// camera.mm_per_px holds: a pinhole of focal length height / mm_per_px
  /// pixels (60 mm: docs/hardware.md). Body motion moves and tilts the
  /// camera from here; without it the view is the same at any height.
  double camera_height_mm = 60.0;
  /// Body motion laid over the scenario (sim::with_body_motion): "flat"
  /// (nominal height, level), "heave" or "ride" (docs/simulator.md, "Body
  /// motion"). Ignored by the constructor taking a custom scenario (which
  /// brings its own Scenario::body).
  std::string body = "flat";
  /// Laser dots of the sensor head (docs/simulator.md, "Laser dots"); none
  /// (count 0, the default): frames are exactly those of a head without lasers.
  core::LaserGeometry lasers;
  /// Brightness of the dots against the LED ring's light, and their speckle.
  double laser_peak_relative = 8.0;
  double laser_speckle_grain_mm = 0.027;  ///< lambda / (2 NA) on the ground
  bool loop = false;           ///< start the scenario again when it ends (daemon)
  std::uint64_t sensor_seed = 7;  ///< fixed-pattern noise of "the" sensor (not the scene)
  sim::SensorModel sensor;        ///< sensor and light numbers (docs/simulator.md)
  /// Blur length (px) from which the texture raster along the motion is
  /// sampled at the pixel pitch instead of half of it (the path integral
  /// smooths along the motion); <= 0: always half (docs/simulator.md).
  double coarse_raster_min_blur_px = 32.0;
  /// Live use (gvsd's sim: source): the asphalt is a periodic texture (period
  /// >= 1.5x the view, a multiple of 36 mm) rendered once into a tile and
  /// resampled for every frame, instead of rendered per frame: about twice
  /// the frame rate on 2 cores. Same statistics, other stones; datasets
  /// (`gvs sim`) and every accuracy figure use the non-periodic texture.
  /// Procedural ground only: a photo ground is sampled directly.
  bool periodic_texture = false;
  /// Live use (gvsd's sim: source): the cheap render of docs/simulator.md,
  /// "Live source": the exposure raster at the pixel pitch s instead of s/2,
  /// the PSF baked into the (periodic_texture) tile once instead of applied
  /// per frame, path integrals as box filters while the view only
  /// translates, table noise, all on the calling thread. Agrees with the
  /// exact render of the same ground within the tolerance stated there;
  /// datasets never use it.
  bool live_fast_render = false;
  /// The ground: "procedural" (the asphalt above) or "photo:FILE[:MM_PER_PIXEL]",
  /// a seamless square photo at MM_PER_PIXEL (default 0.2) in randomised,
  /// blended tiles (docs/simulator.md, "Photographed ground"; syntax:
  /// sim::parse_ground). config() reports the canonical text.
  std::string ground = "procedural";
};

/// One rendered frame with its record and truth.
struct SimFrame {
  cv::Mat gray;  ///< CV_8UC1, camera.height_px x camera.width_px
  FrameRecord record;
  TruthRecord truth;
};

/// Names of the built-in scenarios: const, sine, accel, brake, skidpad, crawl, stop, spin.
std::vector<std::string> scenario_names();
/// Names of the body motions: flat, heave, ride.
std::vector<std::string> body_motion_names();

class Simulator {
 public:
  /// Throws std::invalid_argument naming the scenario (and the known ones) or
  /// the out-of-range setting.
  explicit Simulator(const SimulatorConfig& config);
  /// Drives a custom scenario (e.g. sim::constant_motion_scenario(vx, vy));
  /// config.scenario is ignored (config() reports the scenario's name).
  Simulator(const SimulatorConfig& config, sim::Scenario scenario);
  ~Simulator();
  Simulator(const Simulator&) = delete;
  Simulator& operator=(const Simulator&) = delete;
  Simulator(Simulator&&) noexcept;
  Simulator& operator=(Simulator&&) noexcept;

  /// The scenario moves the body (height, pitch, roll): the truth then
  /// holds height_mm, pitch_deg and roll_deg.
  [[nodiscard]] bool has_body_motion() const;

  /// Renders the next frame into `out` (reusing its buffer). Returns false when
  /// the run is over (never when looping).
  bool next(SimFrame& out);

  /// Exposure for the frames from the next one on (closed-loop exposure control).
  /// Photons follow the lit time (pulses with the LED overdriven); the gain
  /// follows like an auto-gain, within SensorModel::max_gain_ratio of the run's
  /// gain, so the mean grey stays near its target. Throws
  /// std::invalid_argument for an impossible plan (exposure <= 0 or longer
  /// than the frame period, pulses outside the exposure, overlapping or
  /// unsorted, or more than kMaxPulses).
  void set_exposure(const core::ExposurePlan& plan);
  [[nodiscard]] const core::ExposurePlan& exposure() const;

  /// Renders frame `index` with `plan` without advancing the run (random
  /// access, e.g. the same instant with different exposures).
  void render(std::int64_t index, const core::ExposurePlan& plan, SimFrame& out);

  [[nodiscard]] const sim::Trajectory& trajectory() const;
  /// Gain set for the run (DN per electron at the configured exposure).
  [[nodiscard]] double run_gain_dn_per_e() const;
  /// Cost breakdown of the last rendered frame.
  [[nodiscard]] const sim::RenderStats& last_render_stats() const;

  [[nodiscard]] const SimulatorConfig& config() const;
  [[nodiscard]] std::size_t frame_count() const;  ///< frames in one pass of the run

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace gvs::drivers
