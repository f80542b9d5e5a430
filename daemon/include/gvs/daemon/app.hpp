// gvsd's main thread: command line, configuration, real-time setup, signals,
// systemd notification and watchdog, health log.
#pragma once

namespace gvs::daemon {

/// `gvsd [--config FILE] [--source URI] [--can URI] [--run-for SECONDS]`.
/// Returns the process exit code: 0 after a clean stop, 1 when start-up
/// failed (the log says why), CLI11's code for a bad command line.
int gvsd_main(int argc, char** argv);

}  // namespace gvs::daemon
