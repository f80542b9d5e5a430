#pragma once
// Made-up frames that take the estimator down the paths the car's frames
// take, before the first real one: its buffers touched, their pages faulted
// in (and locked, with [threads] lock_on_fault), its code paged in. Without
// this the first real frames of each kind cost up to twice their time, which
// at 250 fps skips frames.

#include <cstddef>
#include <vector>

#include <opencv2/core.hpp>

#include "gvs/core/frame.hpp"
#include "gvs/drivers/frame_slot.hpp"

namespace gvs::daemon {

class FrameEstimator;

/// A sharp pair, 3 ms streaks, a short strobe and a double pulse over a
/// made-up ground texture, 60 fps apart. Each is drawn into a slot the
/// caller owns, so warming up leaves no frame buffer behind in the heap.
class WarmUpFrames {
 public:
  /// Setup: allocates the texture (about 2 MB for 512x384, freed with this).
  explicit WarmUpFrames(const core::CameraGeometry& camera);
  [[nodiscard]] std::size_t size() const noexcept;
  /// Frame `i` into `slot`, whose grey image must be CV_8UC1 of the
  /// camera's size (FrameSource::prepare made it so): no allocation.
  void draw(std::size_t i, drivers::FrameSlot& slot) noexcept;

 private:
  cv::Mat texture_;           ///< CV_32F, the frame plus a margin to shift and smear in
  std::vector<float> row_;    ///< one row being summed
};

/// Runs `estimator` over every frame of `frames`, drawn one after the other
/// into `scratch`, then resets it: nothing of them stays in its history or
/// in its exception count.
void warm_up(FrameEstimator& estimator, WarmUpFrames& frames, drivers::FrameSlot& scratch) noexcept;

}  // namespace gvs::daemon
