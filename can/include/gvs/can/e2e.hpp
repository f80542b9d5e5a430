// End-to-end protection laid out as AUTOSAR E2E profile 2 (one data ID per
// message): byte 0 is a CRC-8/AUTOSAR over bytes 1..7 followed by the data
// ID; the low nibble of byte 1 is an alive counter 0..15 that steps by one
// per message of that ID. The data ID is the low byte of the CAN ID.
// See docs/can-interface.md for a worked example.
#pragma once

#include <cstddef>
#include <cstdint>

#include "gvs/can/frame.hpp"

namespace gvs::can {

/// CRC-8/AUTOSAR (SAE J1850 family, AUTOSAR SWS_Crc "Crc_CalculateCRC8H2F"):
/// polynomial 0x2F, initial value 0xFF, no reflection, final XOR 0xFF.
/// Check value over the ASCII bytes "123456789" is 0xDF.
/// `start` continues a CRC over several blocks: pass the previous result.
std::uint8_t crc8_autosar(const std::uint8_t* bytes, std::size_t count,
                          std::uint8_t start = 0x00) noexcept;

/// The E2E data ID of a message: the low byte of its CAN ID.
constexpr std::uint8_t e2e_data_id(std::uint32_t can_id) {
  return static_cast<std::uint8_t>(can_id & 0xFFu);
}

/// The CRC that byte 0 must hold: CRC-8/AUTOSAR over data[1..7] then data_id.
std::uint8_t e2e_crc(const CanFrame& frame, std::uint8_t data_id) noexcept;

/// Writes the alive counter (low nibble of byte 1, other bits kept) and then
/// the CRC (byte 0). The frame must be 8 bytes long.
void e2e_protect(CanFrame& frame, std::uint8_t counter) noexcept;

/// The alive counter of a protected frame.
constexpr std::uint8_t e2e_counter(const CanFrame& frame) {
  return static_cast<std::uint8_t>(frame.data[1] & 0x0Fu);
}

/// True when the frame is 8 bytes long and byte 0 matches its CRC.
bool e2e_crc_ok(const CanFrame& frame) noexcept;

/// How far the counter moved from `previous` to `current`, 0..15 (1 = no loss).
constexpr std::uint8_t e2e_counter_delta(std::uint8_t previous, std::uint8_t current) {
  return static_cast<std::uint8_t>((current - previous) & 0x0Fu);
}

}  // namespace gvs::can
