// A camera for the in-process pipeline tests: 100 fps, every frame of a car
// at 10 m/s straight ahead (as truth), until stopped; and the configuration
// that keeps the pipeline's threads off real-time priorities.
#pragma once

#include <algorithm>
#include <atomic>

#include "gvs/drivers/clock.hpp"
#include "gvs/daemon/config.hpp"
#include "gvs/drivers/frame_source.hpp"

namespace gvs::daemon::testing {

class SteadyCamera final : public drivers::FrameSource {
 public:
  std::string describe() const override { return "steady"; }
  core::CameraGeometry geometry() const override { return {64, 48, 0.1, 0.0}; }
  double nominal_fps() const override { return 100.0; }
  void prepare(drivers::FrameSlot& slot) override { slot.view.gray.create(48, 64, CV_8UC1); }
  drivers::SourceStatus next(drivers::FrameSlot& slot, const std::atomic<bool>& stop) noexcept override {
    if (base_ns_ < 0) base_ns_ = drivers::mono_now_ns();
    const std::int64_t due = base_ns_ + (index_ + 1) * kPeriodNs;
    while (drivers::mono_now_ns() < due) {
      if (stop.load()) return drivers::SourceStatus::stopped;
      drivers::sleep_until_ns(std::min(due, drivers::mono_now_ns() + 5 * drivers::kNsPerMs));
    }
    slot.view.index = index_++;
    slot.view.t_ns = due - drivers::kNsPerMs;
    slot.view.exposure.exposure_us = 1000.0;
    slot.truth = drivers::FrameTruth{true, 10.0, 0.0, 10.0, 0.0, 0.0};
    return drivers::SourceStatus::frame;
  }
  void set_exposure(const core::ExposurePlan&) noexcept override {}
  bool controls_exposure() const override { return false; }

 private:
  static constexpr std::int64_t kPeriodNs = 10 * drivers::kNsPerMs;
  std::int64_t index_ = 0;
  std::int64_t base_ns_ = -1;
};

/// Defaults, with every thread at normal priority: the tests must not take
/// the shared machine's CPUs.
inline DaemonConfig unprivileged_config() {
  DaemonConfig c;
  c.capture_thread.priority = 0;
  c.processing_thread.priority = 0;
  c.sender_thread.priority = 0;
  c.prefault_stack_kb = 64;
  return c;
}

}  // namespace gvs::daemon::testing
