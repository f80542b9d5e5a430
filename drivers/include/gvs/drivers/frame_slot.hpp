// One preallocated frame buffer of the capture ring.
#pragma once

#include <cstdint>
#include <optional>

#include "gvs/core/reject_reason.hpp"
#include "gvs/core/frame.hpp"

namespace gvs::drivers {

/// Ground truth carried along with a frame by sources that know it (the
/// simulator; replay of a dataset with truth.csv). Vehicle axes, sensor point.
struct FrameTruth {
  bool known = false;
  double vx_mps = 0.0;
  double vy_mps = 0.0;
  double speed_mps = 0.0;
  double direction_deg = 0.0;
  double yaw_rate_dps = 0.0;
};

/// A ring slot. `view.gray` owns a pixel buffer allocated once at start-up
/// (FrameSource::prepare); sources fill it in place.
struct FrameSlot {
  core::FrameView view;            ///< pixels, source index, exposure start (monotonic ns), exposure
  std::int64_t captured_ns = 0;   ///< monotonic time the capture thread received the frame
  std::uint64_t sequence = 0;     ///< capture order, 1, 2, ... (gaps: frames the ring had no room for)
  FrameTruth truth;
  /// Set by the source (or the light check) when it could not deliver a
  /// usable frame (unreadable, wrong size, no exposure time, ...): the frame
  /// gets no estimate, its method names the reason, and it is counted.
  std::optional<core::RejectReason> defect;
};

}  // namespace gvs::drivers
