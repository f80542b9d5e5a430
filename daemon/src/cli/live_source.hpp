// The live frame source for `gvs record` and `gvs snapshot --source`: gvsd's
// own sources (libcamera[:ID], sim:SCENARIO, replay:DIR) built from a gvsd
// configuration, outside gvsd.
#pragma once

#include <atomic>
#include <memory>
#include <string>

#include "gvs/daemon/config.hpp"
#include "gvs/drivers/frame_source.hpp"

namespace gvs::cli {

struct LiveSource {
  daemon::DaemonConfig config;
  std::unique_ptr<drivers::FrameSource> source;
  drivers::FrameSlot slot;  ///< prepared: next() fills it
};

/// Reads `config_file` (built-in defaults when empty), `source_uri`
/// overrides [source] uri; builds and prepares the source at the configured
/// initial exposure. Throws with the source's message.
LiveSource open_live_source(const std::string& config_file, const std::string& source_uri);

/// Raised by SIGINT / SIGTERM once install_stop_signals() ran.
std::atomic<bool>& stop_requested();
void install_stop_signals();

}  // namespace gvs::cli
