// What the processing thread hands to the CAN sender through the seqlock.
#pragma once

#include <cstdint>

#include "gvs/core/estimate.hpp"

namespace gvs::daemon {

struct PublishedEstimate {
  std::uint64_t sequence = 0;      ///< 0: nothing published yet; then 1, 2, ... per processed frame
  core::VelocityEstimate estimate;  ///< at the car's reference point; t_ns = mid-exposure, monotonic
  std::int64_t captured_ns = 0;    ///< when the capture thread received the frame (monotonic)
  std::int64_t published_ns = 0;   ///< when the processing thread published this (monotonic)
  std::int64_t processing_ns = 0;  ///< time spent in the estimator
  double exposure_us = 0.0;        ///< exposure of the frame
  /// false: the plausibility gate held the estimate back (sent with every
  /// Valid bit 0); the estimate itself is kept as measured, for the log.
  bool plausible = true;
};

}  // namespace gvs::daemon
