// One frame through the estimator, exactly as gvsd's processing thread does
// it: sanity checks on the frame and its timing, then the estimator. `gvs
// replay` uses the same class, so replayed figures are the daemon's figures.
#pragma once

#include <cstdint>
#include <memory>

#include "gvs/dsp/vocabulary.hpp"
#include "gvs/core/estimate.hpp"
#include "gvs/dsp/estimator.hpp"
#include "gvs/core/frame.hpp"
#include "gvs/core/laser_geometry.hpp"
#include "gvs/dsp/laser_dots.hpp"

namespace gvs::dsp {

/// Why frames got no estimate before reaching the estimator.
struct FrameRejectCounters {
  RejectCounts by_reason{};
  std::uint64_t time_gap = 0;  ///< gap long enough to forget history (not a reject)

  [[nodiscard]] std::uint64_t of(RejectReason r) const { return by_reason[static_cast<std::size_t>(r)]; }
  /// Frames that got no estimate because of their input.
  [[nodiscard]] std::uint64_t total() const {
    std::uint64_t n = 0;
    for (const std::uint64_t c : by_reason) n += c;
    return n;
  }
};

struct FrameProcessorConfig {
  EstimatorConfig estimator;
  double max_exposure_us = 100000.0;  ///< longer is treated as a broken frame
  double max_gap_s = 0.5;             ///< a longer gap resets pair history
  /// The head's laser dots (none: count 0). With them every frame's dots are
  /// found, masked out of what the estimator sees, and when all are found
  /// the estimate carries the ride height and its speed is scaled with it
  /// (ScaleSource::laser_dots); docs/estimator.md, "Height from the laser dots".
  core::LaserGeometry lasers;
  /// Height where camera.mm_per_px holds (camera.json height_mm; 60 mm).
  double nominal_height_mm = 60.0;
  /// Find the dots but do not correct the speed (for measuring what the
  /// correction does; the dots are still masked).
  bool correct_scale = true;
};

class FrameProcessor {
 public:
  /// Builds the estimator (may throw std::invalid_argument naming the method).
  explicit FrameProcessor(const FrameProcessorConfig& config);

  /// No allocation after the first frame of the configured size. Bad frames
  /// are answered with no estimate; what the estimator itself throws
  /// (cv::Exception from OpenCV) passes through to the caller (gvsd catches
  /// it in FrameEstimator::estimate).
  core::VelocityEstimate process(const core::FrameView& frame);
  void reset() noexcept;
  /// A frame the source could not deliver (RejectReason::unreadable, ...):
  /// no estimate, counted under its reason; the estimator keeps its
  /// history, so the next good frame is measured as usual.
  core::VelocityEstimate reject(const core::FrameView& frame, RejectReason reason) noexcept;

  [[nodiscard]] const FrameRejectCounters& rejects() const { return rejects_; }
  [[nodiscard]] const FrameProcessorConfig& config() const { return config_; }
  /// The dots of the last processed frame (none without lasers).
  [[nodiscard]] const LaserDotResult& last_dots() const { return dots_; }

 private:
  FrameProcessorConfig config_;
  std::unique_ptr<VelocityEstimator> estimator_;
  std::unique_ptr<LaserDotFinder> finder_;  ///< with lasers only
  cv::Mat masked_;                          ///< the frame with the dots masked out
  LaserDotResult dots_;
  FrameRejectCounters rejects_;
  bool have_previous_ = false;
  std::int64_t previous_t_ns_ = 0;
};

}  // namespace gvs::dsp
