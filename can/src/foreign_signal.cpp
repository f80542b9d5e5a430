#include "gvs/can/foreign_signal.hpp"

#include <stdexcept>
#include <string>

namespace gvs::can {

namespace {

/// The bits the signal occupies, in order from its most significant bit
/// (Motorola) or least significant bit (Intel); returns the highest byte
/// touched + 1, or 0 when the signal runs off the 8 bytes.
template <typename Visit>
int walk_bits(const ForeignSignal& s, Visit&& visit) noexcept {
  int bit = s.start_bit;
  int bytes = 0;
  for (int i = 0; i < s.length; ++i) {
    if (bit < 0 || bit > 63) return 0;
    visit(i, bit);
    if (bit / 8 + 1 > bytes) bytes = bit / 8 + 1;
    if (s.big_endian) {
      bit = bit % 8 == 0 ? bit + 15 : bit - 1;  // down through the byte, then the next byte's MSB
    } else {
      ++bit;
    }
  }
  return bytes;
}

}  // namespace

void validate(const ForeignSignal& s) {
  if (s.length < 1 || s.length > 32) {
    throw std::invalid_argument("signal length " + std::to_string(s.length) + " bits: must be 1 .. 32");
  }
  if (walk_bits(s, [](int, int) {}) == 0) {
    throw std::invalid_argument("signal of " + std::to_string(s.length) + " bits from start bit " +
                                std::to_string(s.start_bit) + (s.big_endian ? " (Motorola)" : " (Intel)") +
                                " runs past the 8 data bytes");
  }
  if (s.can_id > (s.extended ? CanFrame::kMaxExtendedId : CanFrame::kMaxStandardId)) {
    throw std::invalid_argument("CAN ID " + std::to_string(s.can_id) + " does not fit " +
                                (s.extended ? "29" : "11") + " bits");
  }
  if (!(s.scale != 0.0)) throw std::invalid_argument("signal scale must not be 0");
}

std::optional<double> read_signal(const CanFrame& frame, const ForeignSignal& s) noexcept {
  if (frame.error || frame.remote || frame.extended != s.extended || frame.id != s.can_id) return std::nullopt;
  std::uint64_t raw = 0;
  const int bytes = walk_bits(s, [&](int i, int bit) {
    const auto b = static_cast<unsigned>(bit);
    const std::uint64_t v = (static_cast<unsigned>(frame.data[b / 8u]) >> (b % 8u)) & 1u;
    // Intel: the i-th bit walked is bit i of the value; Motorola: from the top.
    const int pos = s.big_endian ? s.length - 1 - i : i;
    raw |= v << pos;
  });
  if (bytes == 0 || bytes > frame.len) return std::nullopt;
  double value = static_cast<double>(raw);
  if (s.is_signed && ((raw >> (s.length - 1)) & 1u) != 0) value -= static_cast<double>(std::uint64_t{1} << s.length);
  return value * s.scale + s.offset;
}

}  // namespace gvs::can
