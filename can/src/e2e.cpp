#include "gvs/can/e2e.hpp"

namespace gvs::can {

std::uint8_t crc8_autosar(const std::uint8_t* bytes, std::size_t count,
                          std::uint8_t start) noexcept {
  // Bitwise MSB-first CRC; `start` is a finished CRC (final XOR applied), so
  // undo the XOR to continue. A fresh CRC starts from 0x00 ^ 0xFF = init 0xFF.
  auto crc = static_cast<std::uint8_t>(start ^ 0xFFu);
  for (std::size_t i = 0; i < count; ++i) {
    crc = static_cast<std::uint8_t>(crc ^ bytes[i]);
    for (int bit = 0; bit < 8; ++bit) {
      const unsigned shifted = static_cast<unsigned>(crc) << 1U;
      crc = static_cast<std::uint8_t>((crc & 0x80U) != 0 ? (shifted ^ 0x2FU) : shifted);
    }
  }
  return static_cast<std::uint8_t>(crc ^ 0xFFu);
}

std::uint8_t e2e_crc(const CanFrame& frame, std::uint8_t data_id) noexcept {
  const std::uint8_t crc = crc8_autosar(frame.data.data() + 1, 7);
  return crc8_autosar(&data_id, 1, crc);
}

void e2e_protect(CanFrame& frame, std::uint8_t counter) noexcept {
  frame.data[1] = static_cast<std::uint8_t>((frame.data[1] & 0xF0u) | (counter & 0x0Fu));
  frame.data[0] = e2e_crc(frame, e2e_data_id(frame.id));
}

bool e2e_crc_ok(const CanFrame& frame) noexcept {
  return frame.len == 8 && !frame.remote && !frame.error &&
         frame.data[0] == e2e_crc(frame, e2e_data_id(frame.id));
}

}  // namespace gvs::can
