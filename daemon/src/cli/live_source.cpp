#include "live_source.hpp"

#include <csignal>

#include "gvs/daemon/source_factory.hpp"

namespace gvs::cli {

namespace {
std::atomic<bool> g_stop{false};
extern "C" void on_stop_signal(int /*sig*/) { g_stop.store(true); }
}  // namespace

std::atomic<bool>& stop_requested() { return g_stop; }

void install_stop_signals() {
  std::signal(SIGINT, on_stop_signal);
  std::signal(SIGTERM, on_stop_signal);
}

LiveSource open_live_source(const std::string& config_file, const std::string& source_uri) {
  LiveSource live;
  if (!config_file.empty()) live.config = daemon::load_config_file(config_file);
  if (!source_uri.empty()) live.config.source_uri = source_uri;
  live.source = daemon::make_frame_source(live.config);
  live.source->prepare(live.slot);
  core::ExposurePlan plan;
  plan.exposure_us = live.config.exposure_initial_us;
  live.source->set_exposure(plan);
  return live;
}

}  // namespace gvs::cli
