// What `gvsd --check-config` runs: every check of gvsd's start-up that
// needs no device, so a configuration it accepts does not fail at start-up
// for a reason a file could have shown.
#pragma once

#include <string>

namespace gvs::daemon {

struct DaemonConfig;

/// After the file was parsed and the command line applied: the source
/// (check_frame_source: URI, simulator settings and scenario, ground photo,
/// replay index, libcamera settings), the estimator built for the source's
/// geometry, the CAN URI's form. Opens no camera, CAN interface, candump file
/// or GPIO/PWM line. Returns the estimator's name; throws a std::exception
/// with the message start-up would give.
std::string check_startup(const DaemonConfig& config);

}  // namespace gvs::daemon
