// The simulated ground camera: procedural asphalt seen by a top-down camera
// on a car driven by a scenario. It is the ground truth behind every figure
// gvs publishes (docs/simulator.md).
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <opencv2/core/mat.hpp>

#include "gvs/drivers/dataset.hpp"
#include "gvs/dsp/frame.hpp"

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
  dsp::CameraGeometry camera;  ///< 512x384 px, 0.1 mm/px, mount yaw 0
  bool loop = false;           ///< start the scenario again when it ends (daemon)
};

/// One rendered frame with its record and truth.
struct SimFrame {
  cv::Mat gray;  ///< CV_8UC1, camera.height_px x camera.width_px
  FrameRecord record;
  TruthRecord truth;
};

/// Names of the built-in scenarios: const, sine, accel, skidpad, crawl, stop, spin.
std::vector<std::string> scenario_names();

class Simulator {
 public:
  /// Throws std::invalid_argument naming the scenario (and the known ones) or
  /// the out-of-range setting.
  explicit Simulator(const SimulatorConfig& config);
  ~Simulator();
  Simulator(const Simulator&) = delete;
  Simulator& operator=(const Simulator&) = delete;
  Simulator(Simulator&&) noexcept;
  Simulator& operator=(Simulator&&) noexcept;

  /// Renders the next frame into `out` (reusing its buffer). Returns false when
  /// the run is over (never when looping).
  bool next(SimFrame& out);

  /// Exposure for the frames from the next one on (closed-loop exposure control).
  void set_exposure(const dsp::ExposurePlan& plan);

  [[nodiscard]] const SimulatorConfig& config() const;
  [[nodiscard]] std::size_t frame_count() const;  ///< frames in one pass of the run

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace gvs::drivers
