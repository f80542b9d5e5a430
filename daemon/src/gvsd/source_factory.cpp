// Builds the frame source named by a URI: sim:SCENARIO, replay:DIR, libcamera[:ID].
#include <stdexcept>

#include "gvs/daemon/config.hpp"
#include "gvs/daemon/frame_source.hpp"
#include "gvs/drivers/simulator.hpp"
#include "replay_source.hpp"
#include "sim_source.hpp"

namespace gvs::daemon {

std::unique_ptr<FrameSource> make_frame_source(const DaemonConfig& config) {
  const std::string& uri = config.source_uri;
  const auto colon = uri.find(':');
  const std::string scheme = uri.substr(0, colon);
  const std::string rest = colon == std::string::npos ? std::string() : uri.substr(colon + 1);

  if (scheme == "sim") {
    if (rest.empty()) throw std::runtime_error("source '" + uri + "': name a scenario, e.g. sim:sine");
    drivers::SimulatorConfig sim;
    sim.scenario = rest;
    sim.fps = config.sim_fps;
    sim.seed = static_cast<std::uint64_t>(config.sim_seed);
    sim.exposure_us = config.exposure_initial_us;
    sim.camera = config.camera;
    sim.loop = true;
    try {
      return std::make_unique<SimSource>(sim);
    } catch (const std::invalid_argument& e) {
      throw std::runtime_error("source '" + uri + "': " + e.what());
    }
  }
  if (scheme == "replay") {
    if (rest.empty()) throw std::runtime_error("source '" + uri + "': name a dataset folder, e.g. replay:/data/run1");
    return std::make_unique<ReplaySource>(rest, config.replay_preload_limit_mb);
  }
  if (scheme == "libcamera") {
    throw std::runtime_error("source '" + uri +
                             "': the libcamera source is not implemented yet (a later issue); "
                             "use sim:SCENARIO or replay:DIR");
  }
  throw std::runtime_error("source '" + uri + "': unknown kind; use sim:SCENARIO, replay:DIR or libcamera[:ID]");
}

}  // namespace gvs::daemon
