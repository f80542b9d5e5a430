#include "gvs/daemon/frame_estimator.hpp"

#include <cmath>
#include <stdexcept>

#include "gvs/dsp/frame_processor.hpp"
#include "gvs/dsp/estimator.hpp"
#include "gvs/core/geometry.hpp"
#include "gvs/drivers/dataset.hpp"

namespace gvs::daemon {

namespace {

/// A dsp estimator from the factory, behind the frame checks of
/// dsp::FrameProcessor: the very code `gvs replay` runs.
class DspEstimator final : public FrameEstimator {
 public:
  explicit DspEstimator(const dsp::FrameProcessorConfig& config) : processor_(config) {}
  core::VelocityEstimate estimate_frame(const drivers::FrameSlot& slot) override {
    if (slot.defect) return processor_.reject(slot.view, *slot.defect);
    return processor_.process(slot.view);
  }
  void reset() noexcept override { processor_.reset(); }
  [[nodiscard]] core::RejectCounts rejected_frames() const noexcept override { return processor_.rejects().by_reason; }
  [[nodiscard]] std::string name() const override { return processor_.config().estimator.method; }

 private:
  dsp::FrameProcessor processor_;
};

/// Reports the truth the source carries (simulator; replay with truth.csv):
/// checks the daemon's timing and CAN path without an estimator's errors.
class TruthEstimator final : public FrameEstimator {
 public:
  core::VelocityEstimate estimate_frame(const drivers::FrameSlot& slot) override {
    const std::int64_t mid_ns = core::mid_exposure_ns(slot.view.t_ns, slot.view.exposure);
    if (!slot.truth.known) return core::no_estimate(slot.view.index, mid_ns, core::Method::none);
    core::VelocityEstimate e;
    e.index = slot.view.index;
    e.t_ns = mid_ns;
    e.has_speed = true;
    e.has_direction = slot.truth.speed_mps >= core::VelocityEstimate::kStandstillMps;
    e.has_yaw_rate = true;
    e.vx_mps = slot.truth.vx_mps;
    e.vy_mps = slot.truth.vy_mps;
    e.speed_mps = slot.truth.speed_mps;
    e.direction_deg = slot.truth.direction_deg;
    e.yaw_rate_dps = slot.truth.yaw_rate_dps;
    e.quality = 1.0;
    e.method = core::Method::truth;
    return e;
  }
  void reset() noexcept override {}
  [[nodiscard]] std::string name() const override { return "truth"; }
};

}  // namespace

core::VelocityEstimate FrameEstimator::estimate(const drivers::FrameSlot& slot) noexcept {
  try {
    return estimate_frame(slot);
  } catch (...) {
    // cv::Exception, std::exception or anything else: one frame lost, never
    // the process. The estimator may have stopped half-way through updating
    // its history, so it starts again from the next frame.
  }
  ++exceptions_;
  reset();
  return core::no_estimate(slot.view.index, core::mid_exposure_ns(slot.view.t_ns, slot.view.exposure),
                          core::Method::estimator_exception);
}

core::LaserGeometry load_configured_lasers(const HeightConfig& height) {
  if (height.source != "lasers") return {};
  if (height.lasers_file.empty()) {
    throw std::runtime_error("[height] source = \"lasers\" needs lasers_file: the file `gvs calibrate height --out` "
                             "wrote (or a camera.json with \"lasers\")");
  }
  try {
    return drivers::load_laser_geometry(height.lasers_file);
  } catch (const drivers::DatasetError& e) {
    throw std::runtime_error(std::string("[height] lasers_file: ") + e.what());
  }
}

std::unique_ptr<FrameEstimator> make_frame_estimator(const std::string& method, const core::CameraGeometry& geometry,
                                                     const HeightConfig& height) {
  dsp::FrameProcessorConfig config;
  config.lasers = load_configured_lasers(height);  // checked with "truth" too: --check-config names a bad file
  config.nominal_height_mm = height.nominal_mm;
  if (method == "truth") return std::make_unique<TruthEstimator>();
  config.estimator.method = method;
  config.estimator.camera = geometry;
  try {
    return std::make_unique<DspEstimator>(config);
  } catch (const std::invalid_argument& e) {
    throw std::runtime_error(std::string("[estimator] method: ") + e.what() +
                             " (or \"truth\": the source's ground truth, for pipeline tests)");
  }
}

void apply_lever_arm(core::VelocityEstimate& e, double lever_arm_x_m, double lever_arm_y_m) noexcept {
  if (lever_arm_x_m == 0.0 && lever_arm_y_m == 0.0) return;
  if (!e.has_yaw_rate || !e.has_velocity_xy()) return;
  const double omega = core::deg_to_rad(e.yaw_rate_dps);
  e.vx_mps += omega * lever_arm_y_m;
  e.vy_mps -= omega * lever_arm_x_m;
  e.speed_mps = std::hypot(e.vx_mps, e.vy_mps);
  e.has_direction = e.speed_mps >= core::VelocityEstimate::kStandstillMps;
  e.direction_deg = e.has_direction ? core::direction_deg({e.vx_mps, e.vy_mps}) : 0.0;
}

}  // namespace gvs::daemon
