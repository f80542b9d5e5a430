// Why a frame got no estimate before reaching the estimator: a defect the
// source reported, or one the frame checks found. Each reason is counted on
// its own and names the estimate's method.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

#include "gvs/core/method.hpp"

namespace gvs::core {

enum class RejectReason : std::uint8_t {
  wrong_size,            ///< pixels of another size or format than the camera geometry
  bad_exposure,          ///< exposure time missing, not positive, not finite or too long
  time_backwards,        ///< the frame's time is not after the previous frame's
  unreadable,            ///< the source had no pixels for the frame
  no_light_in_exposure,  ///< the light driver fired no light in the exposure
  no_exposure_metadata,  ///< the camera did not report the exposure time
};

struct RejectReasonInfo {
  RejectReason reason;
  Method method;  ///< the estimate's method; its word names the reason in logs
};

inline constexpr RejectReasonInfo kRejectReasons[] = {
    {RejectReason::wrong_size, Method::wrong_size},
    {RejectReason::bad_exposure, Method::bad_exposure},
    {RejectReason::time_backwards, Method::time_backwards},
    {RejectReason::unreadable, Method::unreadable},
    {RejectReason::no_light_in_exposure, Method::no_light_in_exposure},
    {RejectReason::no_exposure_metadata, Method::no_exposure_metadata},
};
inline constexpr std::size_t kRejectReasonCount = std::size(kRejectReasons);

namespace detail {
constexpr bool reject_reasons_in_enum_order() {
  for (std::size_t i = 0; i < kRejectReasonCount; ++i) {
    if (static_cast<std::size_t>(kRejectReasons[i].reason) != i) return false;
  }
  return true;
}
}  // namespace detail
static_assert(detail::reject_reasons_in_enum_order(), "kRejectReasons must list every RejectReason in enum order");

constexpr Method reject_method(RejectReason r) { return kRejectReasons[static_cast<std::size_t>(r)].method; }
/// The reason's word (the estimates CSV word of its method).
constexpr const char* reject_word(RejectReason r) { return method_word(reject_method(r)); }

/// Frames rejected so far, per reason (index: RejectReason).
using RejectCounts = std::array<std::uint64_t, kRejectReasonCount>;

}  // namespace gvs::core
