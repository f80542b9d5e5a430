// Builds the frame source named by a URI: sim:SCENARIO, replay:DIR, libcamera[:ID].
#include "gvs/daemon/source_factory.hpp"

#include <stdexcept>

#include <spdlog/spdlog.h>

#include "gvs/daemon/config.hpp"
#include "gvs/drivers/replay_source.hpp"
#include "gvs/daemon/frame_estimator.hpp"
#include "gvs/drivers/sim_source.hpp"
#include "gvs/drivers/simulator.hpp"

namespace gvs::daemon {

drivers::LibcameraSettings libcamera_settings(const DaemonConfig& config, const std::string& camera_id) {
  drivers::LibcameraSettings s;
  s.camera_id = camera_id;
  s.camera = config.camera;
  s.fps = config.libcamera_fps;
  if (!drivers::parse_camera_pixel_format(config.libcamera_pixel_format, s.pixel_format)) {
    throw std::runtime_error(config.origin + ": [libcamera] pixel_format '" + config.libcamera_pixel_format +
                             "' is not R8 or YUV420");
  }
  s.buffer_count = config.libcamera_buffer_count;
  s.exposure_initial_us = config.exposure_initial_us;
  s.exposure_min_us = config.libcamera_exposure_min_us;
  s.exposure_max_us = config.exposure_max_us;
  s.gain_min = config.libcamera_gain_min;
  s.gain_max = config.libcamera_gain_max;
  s.stall_periods = config.libcamera_stall_periods;
  s.retry_interval_ms = config.libcamera_retry_interval_ms;
  return s;
}

namespace {

struct SourceUri {
  std::string scheme;  ///< sim, replay or libcamera
  std::string rest;    ///< scenario, folder or camera id
};

SourceUri split_source_uri(const std::string& uri) {
  const auto colon = uri.find(':');
  SourceUri u{uri.substr(0, colon), colon == std::string::npos ? std::string() : uri.substr(colon + 1)};
  if (u.scheme == "sim" && u.rest.empty()) throw std::runtime_error("source '" + uri + "': name a scenario, e.g. sim:sine");
  if (u.scheme == "replay" && u.rest.empty()) {
    throw std::runtime_error("source '" + uri + "': name a dataset folder, e.g. replay:/data/run1");
  }
  if (u.scheme != "sim" && u.scheme != "replay" && u.scheme != "libcamera") {
    throw std::runtime_error("source '" + uri + "': unknown kind; use sim:SCENARIO, replay:DIR or libcamera[:ID]");
  }
  return u;
}

drivers::SimulatorConfig sim_config(const DaemonConfig& config, const std::string& scenario) {
  drivers::SimulatorConfig sim;
  sim.scenario = scenario;
  sim.fps = config.sim_fps;
  sim.seed = static_cast<std::uint64_t>(config.sim_seed);
  sim.ground = config.sim_ground;
  sim.body = config.sim_body;
  // The simulated head carries the lasers gvsd is configured to read, at the
  // nominal height they are measured against.
  sim.lasers = load_configured_lasers(config.height);
  if (config.height.source != "none") sim.camera_height_mm = config.height.nominal_mm;
  sim.exposure_us = config.exposure_initial_us;
  sim.camera = config.camera;
  sim.loop = true;
  // Rendered live beside the estimator: the cheap periodic texture
  // (SimulatorConfig::periodic_texture, docs/simulator.md).
  sim.periodic_texture = true;
  sim.live_fast_render = true;
  return sim;
}

}  // namespace

std::unique_ptr<drivers::FrameSource> make_frame_source(const DaemonConfig& config) {
  const std::string& uri = config.source_uri;
  const SourceUri u = split_source_uri(uri);
  if (u.scheme == "sim") {
    try {
      return std::make_unique<drivers::SimSource>(sim_config(config, u.rest));
    } catch (const std::invalid_argument& e) {
      throw std::runtime_error("source '" + uri + "': " + e.what());
    }
  }
  if (u.scheme == "replay") {
    auto replay = std::make_unique<drivers::ReplaySource>(u.rest, config.replay_window_mb);
    for (const std::string& w : replay->take_log_lines()) spdlog::warn("{}", w);
    return replay;
  }
  try {
    return std::make_unique<drivers::LibcameraSource>(drivers::make_libcamera_device(),
                                                      libcamera_settings(config, u.rest));
  } catch (const std::runtime_error& e) {
    throw std::runtime_error("source '" + uri + "': " + e.what());
  }
}

CheckedSource check_frame_source(const DaemonConfig& config) {
  const std::string& uri = config.source_uri;
  const SourceUri u = split_source_uri(uri);
  if (u.scheme == "sim") {
    try {
      // The simulator checks its settings, builds the scenario and loads the
      // ground as SimSource does, without the first live render.
      const drivers::Simulator sim(sim_config(config, u.rest));
    } catch (const std::invalid_argument& e) {
      throw std::runtime_error("source '" + uri + "': " + e.what());
    }
    return {config.camera, config.sim_fps};
  }
  if (u.scheme == "replay") {
    const drivers::ReplaySource::Checked replay = drivers::ReplaySource::check(u.rest);
    return {replay.geometry, replay.fps};
  }
  try {
    (void)libcamera_settings(config, u.rest);
  } catch (const std::runtime_error& e) {
    throw std::runtime_error("source '" + uri + "': " + e.what());
  }
  return {config.camera, config.libcamera_fps};
}

}  // namespace gvs::daemon
