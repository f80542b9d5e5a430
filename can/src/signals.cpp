#include "gvs/can/signals.hpp"

#include <cmath>

namespace gvs::can {

std::string_view state_name(std::uint8_t code) noexcept {
  switch (code) {
    case 0: return "init";
    case 1: return "running";
    case 2: return "degraded";
    case 3: return "fault";
    case 4: return "stopping";
    default: return "unknown";
  }
}

std::uint64_t get_raw_bits(const CanFrame& frame, const SignalSpec& sig) noexcept {
  std::uint64_t word = 0;
  for (std::size_t i = 0; i < 8; ++i) word |= std::uint64_t{frame.data[i]} << (8 * i);
  const std::uint64_t mask = sig.length >= 64 ? ~std::uint64_t{0} : (std::uint64_t{1} << sig.length) - 1;
  return (word >> sig.start_bit) & mask;
}

std::int64_t get_raw(const CanFrame& frame, const SignalSpec& sig) noexcept {
  const std::uint64_t bits = get_raw_bits(frame, sig);
  if (!sig.is_signed || sig.length >= 64) return static_cast<std::int64_t>(bits);
  const std::uint64_t sign = std::uint64_t{1} << (sig.length - 1);
  // Two's complement sign extension: (bits ^ sign) - sign.
  return static_cast<std::int64_t>(bits ^ sign) - static_cast<std::int64_t>(sign);
}

void set_raw(CanFrame& frame, const SignalSpec& sig, std::int64_t raw) noexcept {
  std::uint64_t word = 0;
  for (std::size_t i = 0; i < 8; ++i) word |= std::uint64_t{frame.data[i]} << (8 * i);
  const std::uint64_t mask = sig.length >= 64 ? ~std::uint64_t{0} : (std::uint64_t{1} << sig.length) - 1;
  word &= ~(mask << sig.start_bit);
  word |= (static_cast<std::uint64_t>(raw) & mask) << sig.start_bit;
  for (std::size_t i = 0; i < 8; ++i) frame.data[i] = static_cast<std::uint8_t>(word >> (8 * i));
}

double to_physical(const SignalSpec& sig, std::int64_t raw) noexcept {
  return static_cast<double>(raw) * sig.scale + sig.offset;
}

std::int64_t to_raw(const SignalSpec& sig, double physical) noexcept {
  double p = std::isnan(physical) ? 0.0 : physical;
  if (p < sig.minimum) p = sig.minimum;
  if (p > sig.maximum) p = sig.maximum;
  return static_cast<std::int64_t>(std::llround((p - sig.offset) / sig.scale));
}

bool in_range(const SignalSpec& sig, double physical) noexcept {
  if (!std::isfinite(physical)) return false;
  const double half_step = sig.scale / 2.0;
  return physical >= sig.minimum - half_step && physical <= sig.maximum + half_step;
}

}  // namespace gvs::can
