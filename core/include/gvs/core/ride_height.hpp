// The sensor's height above the ground and the ground plane's tilt, and
// where the speed's scale came from.
//
// The ground scale (mm per pixel) is proportional to the camera's height
// (docs/hardware.md), so a speed is only as good as the height it was
// scaled with. A measured height (laser dots in the frame, or an external
// distance sensor on CAN) corrects it; without one the speed rests on the
// nominal height of the calibration and the bus says so.
#pragma once

#include <cstdint>

namespace gvs::core {

/// Which height the speed's scale rests on. Its code is the CAN signal
/// GVS_ScaleSource (docs/can-interface.md).
enum class ScaleSource : std::uint8_t {
  nominal = 0,     ///< the calibration's fixed height: uncorrected for heave, pitch, roll
  laser_dots = 1,  ///< measured in this frame by the laser dots
  external = 2,    ///< a distance sensor's height received on CAN
};

/// The geometry of the ground under the sensor at one instant, ISO 8855
/// (positive pitch nose down, positive roll right side down, as the
/// simulator's truth). Fields without their `has_` flag are meaningless.
struct RideHeight {
  bool has_height = false;
  double height_mm = 0.0;  ///< camera's optical centre above the ground, along the vehicle z axis
  bool has_pitch = false;
  double pitch_deg = 0.0;
  bool has_roll = false;
  double roll_deg = 0.0;

  /// Both angles of the plane: what the scale correction's tilt needs.
  [[nodiscard]] bool has_tilt() const { return has_pitch && has_roll; }
};

}  // namespace gvs::core
