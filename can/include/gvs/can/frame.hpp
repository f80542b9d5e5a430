// One classical CAN frame, independent of the Linux struct can_frame so the
// codec and the monitor build and test anywhere.
#pragma once

#include <array>
#include <cstdint>

namespace gvs::can {

/// A classical CAN 2.0 frame (at most 8 data bytes).
struct CanFrame {
  static constexpr std::uint32_t kMaxStandardId = 0x7FF;
  static constexpr std::uint32_t kMaxExtendedId = 0x1FFFFFFF;

  std::uint32_t id = 0;     ///< 11-bit (standard) or 29-bit (extended) identifier
  bool extended = false;    ///< 29-bit identifier
  bool remote = false;      ///< remote transmission request (no data)
  bool error = false;       ///< Linux error frame: `id` holds the CAN_ERR_* class bits
  std::uint8_t len = 0;     ///< data length, 0..8
  std::array<std::uint8_t, 8> data{};
};

}  // namespace gvs::can
