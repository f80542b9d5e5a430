// A signal of another node's message, described as its DBC line describes
// it, read out of received frames: gvsd takes the camera's height from an
// external distance sensor this way (docs/can-interface.md, "External
// height").
//
//   SG_ Height : 7|16@0+ (0.01,0) [0|655.35] "mm"   (Motorola, MSB at bit 7)
//   -> ForeignSignal{.can_id = 0x520, .start_bit = 7, .length = 16,
//                    .big_endian = true, .scale = 0.01}
//   frame 520#1770000000000000 -> raw 0x1770 = 6000 -> 60.00 mm
//
// Bit numbering as in DBC files: bit k is bit (k % 8) of byte k / 8. Intel
// (@1) signals start at their least significant bit and grow upwards;
// Motorola (@0) signals start at their most significant bit and run down
// through the byte, then on into the most significant bit of the next byte.
#pragma once

#include <cstdint>
#include <optional>

#include "gvs/can/frame.hpp"

namespace gvs::can {

struct ForeignSignal {
  std::uint32_t can_id = 0;
  bool extended = false;  ///< 29-bit identifier
  std::uint8_t start_bit = 0;
  std::uint8_t length = 16;  ///< 1 .. 32 bits
  bool big_endian = false;   ///< Motorola (@0); false = Intel (@1)
  bool is_signed = false;
  double scale = 1.0;  ///< physical = raw * scale + offset
  double offset = 0.0;
};

/// Throws std::invalid_argument (naming what is wrong) when the signal cannot
/// lie in an 8-byte frame or its ID does not fit its format.
void validate(const ForeignSignal& signal);

/// The signal's physical value in `frame`, or nothing when the frame is not
/// the signal's message (other ID or format, remote or error frame) or too
/// short to hold it. Never throws.
[[nodiscard]] std::optional<double> read_signal(const CanFrame& frame, const ForeignSignal& signal) noexcept;

}  // namespace gvs::can
