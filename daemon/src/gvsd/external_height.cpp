#include "gvs/daemon/external_height.hpp"

#include <cmath>

namespace gvs::daemon {

can::ForeignSignal external_height_signal(const HeightConfig& c) noexcept {
  can::ForeignSignal s;
  s.can_id = c.can_id;
  s.extended = c.extended;
  s.start_bit = static_cast<std::uint8_t>(c.start_bit);
  s.length = static_cast<std::uint8_t>(c.length);
  s.big_endian = c.byte_order == "motorola";
  s.is_signed = c.is_signed;
  s.scale = c.scale;
  s.offset = c.offset_mm;
  return s;
}

bool apply_external_height(core::VelocityEstimate& e, double height_mm, double nominal_mm) noexcept {
  if (e.scale_source != core::ScaleSource::nominal || !(nominal_mm > 0.0)) return false;
  const double k = height_mm / nominal_mm;
  if (!(std::fabs(k - 1.0) <= kMaxHeightChange)) return false;
  e.vx_mps *= k;
  e.vy_mps *= k;
  e.speed_mps *= k;
  e.ride.has_height = true;
  e.ride.height_mm = height_mm;
  e.scale_source = core::ScaleSource::external;
  return true;
}

}  // namespace gvs::daemon
