// A camera for the pipeline tests: `frames` frames at `fps`, every one of
// a car at 10 m/s, 2 deg (its truth), then silent until stopped.
#pragma once

#include <algorithm>
#include <atomic>
#include <string>

#include "gvs/drivers/clock.hpp"
#include "gvs/drivers/frame_source.hpp"

namespace gvs::daemon::testing {

/// A camera at `fps` that delivers `frames` frames (all of a car at 10 m/s,
/// 2 deg) and then goes silent until stopped.
class ScriptedCamera final : public drivers::FrameSource {
 public:
  ScriptedCamera(double fps, std::int64_t frames) : period_ns_(static_cast<std::int64_t>(1e9 / fps)), frames_(frames) {}
  std::string describe() const override { return "scripted"; }
  core::CameraGeometry geometry() const override { return {64, 48, 0.1, 0.0}; }
  double nominal_fps() const override { return 1e9 / static_cast<double>(period_ns_); }
  void prepare(drivers::FrameSlot& slot) override { slot.view.gray.create(48, 64, CV_8UC1); }
  drivers::SourceStatus next(drivers::FrameSlot& slot, const std::atomic<bool>& stop) noexcept override {
    if (base_ns_ < 0) base_ns_ = drivers::mono_now_ns();
    if (index_ >= frames_) {
      silent_since_ns.store(silent_since_ns.load() < 0 ? drivers::mono_now_ns() : silent_since_ns.load());
      while (!stop.load()) drivers::sleep_until_ns(drivers::mono_now_ns() + drivers::kNsPerMs);
      return drivers::SourceStatus::stopped;
    }
    const std::int64_t due = base_ns_ + (index_ + 1) * period_ns_;
    while (drivers::mono_now_ns() < due) {
      if (stop.load()) return drivers::SourceStatus::stopped;
      drivers::sleep_until_ns(std::min(due, drivers::mono_now_ns() + 5 * drivers::kNsPerMs));
    }
    slot.view.index = index_++;
    slot.view.t_ns = due - 1'000'000;
    slot.view.exposure = plan_;
    slot.view.exposure.exposure_us = 1000.0;
    slot.truth = drivers::FrameTruth{true, 9.99391, 0.34899, 10.0, 2.0, 0.0};
    return drivers::SourceStatus::frame;
  }
  void set_exposure(const core::ExposurePlan& plan) noexcept override {
    plan_ = plan;
    last_exposure_us.store(plan.exposure_us);
    exposure_calls.fetch_add(1);
  }
  bool controls_exposure() const override { return true; }

  std::atomic<double> last_exposure_us{0.0};
  std::atomic<int> exposure_calls{0};
  std::atomic<std::int64_t> silent_since_ns{-1};

 private:
  std::int64_t period_ns_;
  std::int64_t frames_;
  std::int64_t index_ = 0;
  std::int64_t base_ns_ = -1;
  core::ExposurePlan plan_;
};

}  // namespace gvs::daemon::testing
