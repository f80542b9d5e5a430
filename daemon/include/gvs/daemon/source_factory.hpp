// gvsd's frame source from its configuration: `[source] uri` names one of
// drivers' sources (`sim:SCENARIO`, `replay:DIR`, `libcamera[:ID]`), and the
// configuration's sections give its settings.
#pragma once

#include <memory>
#include <string>

#include "gvs/core/geometry.hpp"
#include "gvs/drivers/frame_source.hpp"
#include "gvs/drivers/libcamera_source.hpp"

namespace gvs::daemon {

struct DaemonConfig;

/// Builds the source named by `config.source_uri`. Throws std::runtime_error
/// (unknown scheme, missing dataset, unknown scenario, no camera) with a
/// message saying what to do.
std::unique_ptr<drivers::FrameSource> make_frame_source(const DaemonConfig& config);

/// The checks make_frame_source runs before it opens a camera: the URI, the
/// simulator's settings, scenario and ground photo, the replay dataset's
/// index, the libcamera settings. Returns the frames' geometry and the frame
/// rate the source would run at; throws std::runtime_error with
/// make_frame_source's message.
struct CheckedSource {
  core::CameraGeometry geometry;
  double fps = 0.0;  ///< the frame rate it would run at
};
CheckedSource check_frame_source(const DaemonConfig& config);

/// The libcamera source's settings from gvsd's configuration ([camera],
/// [exposure], [libcamera]); `camera_id` from the source URI.
drivers::LibcameraSettings libcamera_settings(const DaemonConfig& config, const std::string& camera_id);

}  // namespace gvs::daemon
