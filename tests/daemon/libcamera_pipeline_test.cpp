// The libcamera source's disappearance inside gvsd's pipeline: the fake
// camera is unplugged while gvsd runs and plugged back in; the CAN log must
// show invalid velocity and a camera fault while it is gone, and valid
// velocity again once it is back.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <thread>

#include "fake_camera_device.hpp"
#include "gvs/can/sink.hpp"
#include "gvs/drivers/clock.hpp"
#include "gvs/drivers/libcamera_source.hpp"
#include "gvs/daemon/pipeline.hpp"
#include "gvsd_test_support.hpp"

namespace gvs::daemon {
namespace {

/// 10 m/s at 2 deg for every good frame (the camera path is under test, not the estimator).
class ConstantEstimator final : public FrameEstimator {
 public:
  core::VelocityEstimate estimate_frame(const drivers::FrameSlot& slot) override {
    const std::int64_t mid_ns = core::mid_exposure_ns(slot.view.t_ns, slot.view.exposure);
    if (slot.defect) return core::no_estimate(slot.view.index, mid_ns, core::reject_method(*slot.defect));
    core::VelocityEstimate e;
    e.index = slot.view.index;
    e.t_ns = mid_ns;
    e.has_speed = true;
    e.has_direction = true;
    e.vx_mps = 9.99391;
    e.vy_mps = 0.34899;
    e.speed_mps = 10.0;
    e.direction_deg = 2.0;
    e.quality = 1.0;
    e.method = core::Method::truth;
    return e;
  }
  void reset() noexcept override {}
  std::string name() const override { return "constant"; }
};

TEST(LibcameraPipeline, UnpluggedCameraGoesOutInvalidWithCameraFaultThenRecovers) {
  const std::string log = (std::filesystem::temp_directory_path() /
                           ("gvs_libcamera_pipeline_" + std::to_string(getpid()) + ".log")).string();
  DaemonConfig c;
  c.capture_thread.priority = 0;
  c.processing_thread.priority = 0;
  c.sender_thread.priority = 0;
  c.prefault_stack_kb = 64;
  c.staleness_limit_ms = 50.0;  // 3 frame periods at 60 fps
  auto cam = std::make_shared<drivers::testing::FakeCamera>();
  cam->fps = 60.0;
  drivers::LibcameraSettings s;
  s.camera = {64, 48, 0.1, 0.0};
  s.fps = 60.0;
  s.exposure_initial_us = 1000.0;
  s.retry_interval_ms = 300.0;
  auto source =
      std::make_unique<drivers::LibcameraSource>(std::make_unique<drivers::testing::FakeCameraDevice>(cam), s);
  const drivers::LibcameraSource* src = source.get();
  Pipeline p(c, std::move(source), std::make_unique<ConstantEstimator>(), can::open_sink("candump:" + log));
  p.start();
  std::this_thread::sleep_for(std::chrono::milliseconds(800));
  const std::int64_t unplugged_real = drivers::real_now_ns();
  cam->present = false;
  std::this_thread::sleep_for(std::chrono::milliseconds(500));
  const std::int64_t replugged_real = drivers::real_now_ns();
  cam->present = true;
  std::this_thread::sleep_for(std::chrono::milliseconds(1200));
  p.request_stop();
  p.join();
  const drivers::CameraHealth h = src->health();

  const auto msgs = testing::read_candump_log(log);
  std::filesystem::remove(log);
  int valid_before = 0, gone_checked = 0, gone_valid = 0, valid_after = 0;
  for (const auto& m : msgs.velocity) {
    const bool valid = m.decoded.velocity.valid || m.decoded.velocity.speed_valid;
    if (m.t_ns > unplugged_real - 600 * drivers::kNsPerMs && m.t_ns < unplugged_real - 20 * drivers::kNsPerMs) {
      valid_before += valid;
    }
    // staleness limit 50 ms + the last frame's age at the unplug (one period) + one CAN period + slack
    if (m.t_ns > unplugged_real + 100 * drivers::kNsPerMs && m.t_ns < replugged_real) {
      ++gone_checked;
      gone_valid += valid;
    }
    if (m.t_ns > replugged_real + 700 * drivers::kNsPerMs) valid_after += valid;
  }
  EXPECT_GE(valid_before, 10) << "frames flow: valid velocity";
  EXPECT_GE(gone_checked, 15);
  EXPECT_EQ(gone_valid, 0) << "no valid velocity while the camera is gone";
  EXPECT_GE(valid_after, 5) << "valid again after the camera came back";

  int fault_statuses = 0, running_after = 0;
  for (const auto& m : msgs.status) {
    const auto& st = m.decoded.status_msg;
    if (m.t_ns > unplugged_real + 150 * drivers::kNsPerMs && m.t_ns < replugged_real) {
      fault_statuses += (st.faults & can::kFaultCamera) != 0 && st.state == can::SensorState::Fault;
    }
    if (m.t_ns > replugged_real + 700 * drivers::kNsPerMs) running_after += st.state == can::SensorState::Running;
  }
  EXPECT_GE(fault_statuses, 2) << "GVS_Status carries the camera fault and state Fault";
  EXPECT_GE(running_after, 1);
  EXPECT_EQ(h.disconnects, 1u);
  EXPECT_GE(h.restarts, 1u);  // more only if a starved machine made the camera look silent
  EXPECT_LE(h.restarts, 3u);
  EXPECT_GT(p.counters().source_errors.load(), 3u) << "the capture thread counts the missing frames";
}

TEST(LibcameraPipeline, ReloadedExposureMaxReachesTheCamera) {
  const std::string log = (std::filesystem::temp_directory_path() /
                           ("gvs_libcamera_reload_" + std::to_string(getpid()) + ".log")).string();
  DaemonConfig c;
  c.capture_thread.priority = 0;
  c.processing_thread.priority = 0;
  c.sender_thread.priority = 0;
  c.prefault_stack_kb = 64;
  c.exposure_mode = "fixed";  // the plan never changes: only the reload can move the camera
  c.exposure_initial_us = 2800.0;
  c.exposure_max_us = 2000.0;
  auto cam = std::make_shared<drivers::testing::FakeCamera>();
  drivers::LibcameraSettings s;
  s.camera = {64, 48, 0.1, 0.0};
  s.fps = cam->fps;
  s.exposure_initial_us = c.exposure_initial_us;
  s.exposure_max_us = c.exposure_max_us;
  Pipeline p(c, std::make_unique<drivers::LibcameraSource>(std::make_unique<drivers::testing::FakeCameraDevice>(cam), s),
             std::make_unique<ConstantEstimator>(), can::open_sink("candump:" + log));
  p.start();
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  const std::int32_t before_us = cam->seen_controls().exposure_us;
  c.exposure_max_us = 3000.0;
  p.apply_reloadable(c);  // what SIGHUP does
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  const std::int32_t after_us = cam->seen_controls().exposure_us;
  p.request_stop();
  p.join();
  std::filesystem::remove(log);
  EXPECT_EQ(before_us, 2000);
  EXPECT_EQ(after_us, 2800) << "the camera follows the reloaded [exposure] max_us";
}

}  // namespace
}  // namespace gvs::daemon
