// The processing thread's view of an estimator: a dsp estimator built by
// name, or "truth" (the source's ground truth, for testing the pipeline
// without an estimator), plus the lever arm to the car's reference point.
#pragma once

#include <cstdint>
#include <memory>
#include <string>

#include "gvs/drivers/frame_slot.hpp"
#include "gvs/core/estimate.hpp"
#include "gvs/core/frame.hpp"
#include "gvs/core/laser_geometry.hpp"
#include "gvs/daemon/config.hpp"

namespace gvs::daemon {

class FrameEstimator {
 public:
  FrameEstimator() = default;
  FrameEstimator(const FrameEstimator&) = delete;
  FrameEstimator& operator=(const FrameEstimator&) = delete;
  virtual ~FrameEstimator() = default;

  /// Real-time path: no throw, no allocation after the first frame. An
  /// exception from estimate_frame (OpenCV throws cv::Exception on inputs it
  /// rejects) ends here: the frame gets no estimate ("estimator-exception"),
  /// it is counted and the estimator is reset, so the process keeps running.
  core::VelocityEstimate estimate(const drivers::FrameSlot& slot) noexcept;
  virtual void reset() noexcept = 0;
  /// Bad input frames so far, per reason (dsp::FrameRejectCounters::by_reason).
  [[nodiscard]] virtual core::RejectCounts rejected_frames() const noexcept { return {}; }
  /// Frames whose estimation threw (caught by estimate()).
  [[nodiscard]] std::uint64_t estimator_exceptions() const noexcept { return exceptions_; }
  /// Back to 0: the warm-up's made-up frames (warm_up.hpp) are not the camera's.
  void clear_exception_count() noexcept { exceptions_ = 0; }
  [[nodiscard]] virtual std::string name() const = 0;

 protected:
  /// The estimation itself; may throw (estimate() catches).
  virtual core::VelocityEstimate estimate_frame(const drivers::FrameSlot& slot) = 0;

 private:
  std::uint64_t exceptions_ = 0;
};

/// "truth" or a dsp::estimator_names() entry. With [height] source =
/// "lasers" the frames' laser dots are found and masked and each estimate is
/// scaled with the height they give (dsp::FrameProcessorConfig::lasers).
/// Throws std::runtime_error naming the method and the allowed ones, or the
/// [height] key and file that cannot be used.
std::unique_ptr<FrameEstimator> make_frame_estimator(const std::string& method, const core::CameraGeometry& geometry,
                                                     const HeightConfig& height = {});

/// [height] lasers_file's geometry when source = "lasers" (none otherwise).
/// Throws std::runtime_error naming the key and the file.
core::LaserGeometry load_configured_lasers(const HeightConfig& height);

/// Moves a sensor-point velocity to the car's reference point. The sensor
/// sits at r = (x, y) metres from the reference point (vehicle axes); for a
/// rigid body v_sensor = v_ref + omega x r, so
///   v_ref_x = v_x + omega * r_y,   v_ref_y = v_y - omega * r_x   (omega in rad/s).
/// Needs the yaw rate: without it the estimate is left at the sensor point.
void apply_lever_arm(core::VelocityEstimate& e, double lever_arm_x_m, double lever_arm_y_m) noexcept;

}  // namespace gvs::daemon
