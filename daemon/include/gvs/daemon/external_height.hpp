// The camera's height from an external distance sensor ([height] source =
// "can"): its signal, and the estimate's scale corrected with it.
#pragma once

#include "gvs/can/foreign_signal.hpp"
#include "gvs/core/estimate.hpp"
#include "gvs/daemon/config.hpp"

namespace gvs::daemon {

/// The [height] keys as the signal the CAN library reads.
can::ForeignSignal external_height_signal(const HeightConfig& c) noexcept;

/// Rescales an estimate made with the nominal height to the measured one.
/// The ground scale of a camera looking straight down is its height over
/// the focal length (pinhole: mm_per_px = h / f, docs/hardware.md), so a
/// velocity measured in pixels scales with the height:
///   v = v_nominal * height_mm / nominal_mm.
/// The yaw rate (an angle per time) does not depend on it. An estimate whose
/// height was measured in the frame (laser dots) keeps it. A height more than
/// kMaxHeightChange from the nominal is not the camera's (a sensor fault, a
/// wrong signal definition): the estimate keeps the nominal scale, flagged
/// uncorrected, and the function returns false.
bool apply_external_height(core::VelocityEstimate& e, double height_mm, double nominal_mm) noexcept;

/// 25 %: 15 mm at 60 mm, beyond heave, kerb strikes (10 mm) and tyre growth.
inline constexpr double kMaxHeightChange = 0.25;

}  // namespace gvs::daemon
