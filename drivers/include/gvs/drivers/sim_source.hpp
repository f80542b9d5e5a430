// `sim:SCENARIO` frame source: the simulator as a 60 fps
// camera in real time. Frame k's exposure starts at base + k/fps on the
// monotonic clock; the scenario loops.
#pragma once

#include <atomic>
#include <cstdint>

#include "gvs/drivers/frame_source.hpp"
#include "gvs/drivers/simulator.hpp"

namespace gvs::drivers {

class SimSource final : public FrameSource {
 public:
  explicit SimSource(const SimulatorConfig& config);

  [[nodiscard]] std::string describe() const override;
  [[nodiscard]] core::CameraGeometry geometry() const override { return config_.camera; }
  [[nodiscard]] double nominal_fps() const override { return config_.fps; }
  void prepare(FrameSlot& slot) override;
  SourceStatus next(FrameSlot& slot, const std::atomic<bool>& stop) noexcept override;
  void set_exposure(const core::ExposurePlan& plan) noexcept override;
  [[nodiscard]] bool controls_exposure() const override { return true; }
  /// "sim: renders 34.2 ms per frame, 29 of 60 fps: the frames it cannot
  /// render in time are dropped, as a camera drops them" while the renderer
  /// is slower than the frame rate; "" otherwise.
  [[nodiscard]] std::string health_text() const override;

 private:
  Simulator sim_;
  SimulatorConfig config_;
  SimFrame scratch_;  ///< record/truth scratch; its gray points at the slot being filled
  core::ExposurePlan plan_;     ///< exposure of the next frame (closed loop)
  std::int64_t period_ns_ = 0;
  std::int64_t base_ns_ = -1;  ///< monotonic start of frame 0's exposure
  std::int64_t next_index_ = 0;
  std::int64_t render_ns_ = 0; ///< how long a render takes (running estimate)
  bool rendered_live_ = false;  ///< render_ns_ comes from next() (not the constructor's cold render)
  std::atomic<std::int64_t> render_ns_shown_{0};  ///< render_ns_ for health_text() (main thread)
};

}  // namespace gvs::drivers
