// Where frames come from: the simulator (sim_source.hpp), a dataset
// (replay_source.hpp), a camera (libcamera_source.hpp). gvsd chooses and
// builds one from its configuration (gvs/daemon/source_factory.hpp).
#pragma once

#include <atomic>
#include <string>
#include <vector>

#include "gvs/drivers/frame_slot.hpp"
#include "gvs/core/frame.hpp"

namespace gvs::drivers {

enum class SourceStatus {
  frame,  ///< the slot holds a new frame
  end,    ///< the source has no more frames (replay finished)
  error,  ///< this frame could not be read; the source may recover
  stopped ///< the stop flag was raised while waiting
};

/// A camera, real or not. next() runs on the capture thread: it waits for
/// the frame's time (paced sources) and fills the slot in place; it never
/// throws and, once prepare() has run on the slot, never allocates.
class FrameSource {
 public:
  FrameSource() = default;
  FrameSource(const FrameSource&) = delete;
  FrameSource& operator=(const FrameSource&) = delete;
  virtual ~FrameSource() = default;

  /// "sim:sine (60 fps, 512x384)" — for the log.
  [[nodiscard]] virtual std::string describe() const = 0;
  /// Geometry of the frames (and of the camera on the car).
  [[nodiscard]] virtual core::CameraGeometry geometry() const = 0;
  /// Nominal frame rate, frames per second.
  [[nodiscard]] virtual double nominal_fps() const = 0;
  /// Start-up: allocates the slot's buffers (called for each ring slot).
  virtual void prepare(FrameSlot& slot) = 0;
  /// Capture thread: waits for and delivers the next frame.
  virtual SourceStatus next(FrameSlot& slot, const std::atomic<bool>& stop) noexcept = 0;
  /// Capture thread: exposure for the frames from the next one on. Sources
  /// without exposure control ignore it.
  virtual void set_exposure(const core::ExposurePlan& plan) noexcept = 0;
  [[nodiscard]] virtual bool controls_exposure() const = 0;
  /// Main thread, also while the capture thread runs (start-up and SIGHUP):
  /// `[exposure] max_us`, for sources that clamp the exposure themselves.
  virtual void set_exposure_max_us(double exposure_max_us) noexcept { (void)exposure_max_us; }
  /// The frames carry the light that reached the sensor (the simulator
  /// renders its strobe, a dataset records it). A real camera reports only
  /// its shutter time: then gvsd stamps each frame with the LED ring's
  /// measured on-times inside the exposure ([light] driver gpio).
  [[nodiscard]] virtual bool frames_carry_light() const { return true; }
  /// Main thread: the source's own counters for the health line ("" when
  /// it has none).
  [[nodiscard]] virtual std::string health_text() const { return {}; }
  /// Main thread: lines to log as warnings that came up since the last
  /// call (a replay's frame that could not be decoded), each once.
  virtual std::vector<std::string> take_log_lines() { return {}; }
};

}  // namespace gvs::drivers
