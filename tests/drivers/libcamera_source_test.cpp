// The libcamera source on the fake camera (tests/drivers/fake_camera_device.hpp):
// camera choice, controls, metadata handling, counters, disappearance and
// recovery.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <thread>

#include "gvs/drivers/clock.hpp"
#include "libcamera_rig.hpp"

namespace gvs::drivers {
namespace {

using testing::FakeCamera;
using testing::FakeCameraDevice;
using testing::LibcameraRig;
using testing::small_settings;
using Rig = LibcameraRig;

TEST(LibcameraSource, ChoosesTheFirstCameraOrTheOneNamed) {
  EXPECT_EQ(choose_camera({"a", "b"}, ""), "a");
  EXPECT_EQ(choose_camera({"a", "b"}, "b"), "b");
}

TEST(LibcameraSource, UnknownCameraIdNamesTheCamerasPresent) {
  try {
    (void)choose_camera({"/base/cam0", "/base/cam1"}, "/base/cam7");
    FAIL() << "an unknown id must be refused";
  } catch (const std::runtime_error& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("'/base/cam7' not found"), std::string::npos) << m;
    EXPECT_NE(m.find("'/base/cam0', '/base/cam1'"), std::string::npos) << m;
    EXPECT_NE(m.find("libcamera:<one of them>"), std::string::npos) << m;
  }
}

TEST(LibcameraSource, NoCameraSaysWhatToCheck) {
  auto cam = std::make_shared<FakeCamera>();
  cam->present = false;
  try {
    LibcameraSource s(std::make_unique<FakeCameraDevice>(cam), small_settings());
    FAIL() << "no camera must stop start-up";
  } catch (const std::runtime_error& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("no camera found"), std::string::npos) << m;
    EXPECT_NE(m.find("/dev/video"), std::string::npos) << m;
    EXPECT_NE(m.find("sim:sine"), std::string::npos) << m;
  }
}

TEST(LibcameraSource, OpensTheCameraByIdWithTheConfiguredStream) {
  LibcameraSettings s = small_settings();
  s.camera_id = "/base/fake/imx296@1a";
  s.pixel_format = CameraPixelFormat::r8;
  Rig rig(s);
  EXPECT_EQ(rig.source->camera_id(), s.camera_id);
  EXPECT_EQ(rig.cam->opens.load(), 1);
  EXPECT_EQ(rig.cam->last_request.width_px, 64);
  EXPECT_EQ(rig.cam->last_request.height_px, 48);
  EXPECT_EQ(rig.cam->last_request.pixel_format, CameraPixelFormat::r8);
  EXPECT_EQ(rig.cam->last_request.buffer_count, 3);
  EXPECT_NE(rig.source->describe().find("libcamera:/base/fake/imx296@1a"), std::string::npos);
}

TEST(LibcameraSource, ExposurePlanBecomesClampedManualControls) {
  LibcameraSettings s = small_settings();
  s.exposure_min_us = 20.0;
  s.exposure_max_us = 3000.0;
  s.gain_min = 1.0;
  s.gain_max = 8.0;
  core::ExposurePlan plan;
  plan.exposure_us = 1500.0;
  CameraControls c = camera_controls_for(plan, s);
  EXPECT_EQ(c.exposure_us, 1500);
  EXPECT_FLOAT_EQ(c.analogue_gain, 2.0F) << "gain makes up for half the exposure";
  EXPECT_EQ(c.frame_duration_us, 20000) << "FrameDurationLimits from 50 fps";
  plan.exposure_us = 5.0;
  c = camera_controls_for(plan, s);
  EXPECT_EQ(c.exposure_us, 20) << "never below exposure_min_us";
  EXPECT_FLOAT_EQ(c.analogue_gain, 8.0F) << "never above gain_max";
  plan.exposure_us = 9000.0;
  c = camera_controls_for(plan, s);
  EXPECT_EQ(c.exposure_us, 3000) << "never above exposure_max_us";
  EXPECT_FLOAT_EQ(c.analogue_gain, 1.0F);
  s.fps = 500.0;  // 2000 us period
  c = camera_controls_for(plan, s);
  EXPECT_EQ(c.exposure_us, 1800) << "never longer than 0.9 of the frame period";
  EXPECT_EQ(c.frame_duration_us, 2000);
}

TEST(LibcameraSource, DeliversPixelsTimestampAndTheExposureActuallyApplied) {
  Rig rig;
  core::ExposurePlan plan;
  plan.exposure_us = 1007.0;  // the fake sensor applies whole 14 us lines: 994 us
  rig.source->set_exposure(plan);
  // Requests queued before the change still carry the old controls.
  for (int i = 0; i < 6; ++i) ASSERT_TRUE(rig.frame());
  const std::int64_t now = mono_now_ns();
  EXPECT_DOUBLE_EQ(rig.slot.view.exposure.exposure_us, 994.0) << "metadata ExposureTime, not the 1007 asked for";
  EXPECT_EQ(rig.slot.view.exposure.pulse_count, 0u);
  EXPECT_EQ(rig.cam->seen_controls().exposure_us, 1007);
  EXPECT_EQ(rig.cam->seen_controls().frame_duration_us, 20000);
  EXPECT_GT(rig.slot.view.t_ns, now - 500 * kNsPerMs) << "SensorTimestamp on the monotonic clock";
  EXPECT_LE(rig.slot.view.t_ns, now);
  EXPECT_FALSE(rig.slot.defect.has_value());
  // Pixels copied row by row past the stride padding (0xEE never shows).
  const auto seq = static_cast<int>(rig.slot.view.index);
  for (int y = 0; y < 48; ++y) {
    for (int x = 0; x < 64; ++x) {
      ASSERT_EQ(rig.slot.view.gray.at<std::uint8_t>(y, x), (x + 3 * y + seq) & 0x7F) << x << "," << y;
    }
  }
}

TEST(LibcameraSource, ReloadedExposureMaxClampsTheCameraFromTheNextFrames) {
  LibcameraSettings s = small_settings();  // 50 fps: 0.9 of the period is 18000 us
  s.exposure_max_us = 2000.0;
  s.gain_min = 1.0;
  s.gain_max = 8.0;
  Rig rig(s);
  core::ExposurePlan plan;
  plan.exposure_us = 2800.0;  // 200 whole 14 us lines: the fake applies it as asked
  rig.source->set_exposure(plan);
  for (int i = 0; i < 6; ++i) ASSERT_TRUE(rig.frame());
  EXPECT_EQ(rig.cam->seen_controls().exposure_us, 2000) << "the start-up limit";

  rig.source->set_exposure_max_us(4000.0);  // SIGHUP, through Pipeline::apply_reloadable
  for (int i = 0; i < 6; ++i) ASSERT_TRUE(rig.frame());
  EXPECT_EQ(rig.cam->seen_controls().exposure_us, 2800) << "the same plan, no longer clamped to 2000";
  EXPECT_FLOAT_EQ(rig.cam->seen_controls().analogue_gain, static_cast<float>(4000.0 / 2800.0))
      << "gain_min at the new exposure_max_us";
  EXPECT_DOUBLE_EQ(rig.slot.view.exposure.exposure_us, 2800.0) << "frames exposed with it";

  plan.exposure_us = 9000.0;
  rig.source->set_exposure(plan);
  for (int i = 0; i < 6; ++i) ASSERT_TRUE(rig.frame());
  EXPECT_EQ(rig.cam->seen_controls().exposure_us, 4000) << "the reloaded limit clamps new plans";

  rig.source->set_exposure_max_us(1000.0);
  for (int i = 0; i < 6; ++i) ASSERT_TRUE(rig.frame());
  EXPECT_EQ(rig.cam->seen_controls().exposure_us, 1000) << "a lower limit too";
  EXPECT_DOUBLE_EQ(rig.slot.view.exposure.exposure_us, FakeCamera::applied_exposure_us(1000));
}

TEST(LibcameraSource, ReusesOneRequestPerBuffer) {
  Rig rig;
  for (int i = 0; i < 12; ++i) ASSERT_TRUE(rig.frame());
  const auto buffers = rig.cam->seen_buffers();
  EXPECT_EQ(buffers.size(), 3u) << "only the three buffers' requests are ever queued";
  for (const auto& [index, count] : buffers) EXPECT_GE(count, 3) << "buffer " << index << " re-queued";
  EXPECT_EQ(rig.source->health().requeue_failures, 0u);
}

TEST(LibcameraSource, CountsSequenceGapsAndKeepsTheIndexGap) {
  Rig rig;
  ASSERT_TRUE(rig.frame());
  ASSERT_TRUE(rig.frame());
  const std::int64_t before = rig.slot.view.index;
  rig.cam->skip_sequences = 3;
  ASSERT_TRUE(rig.frame());
  // Frames may already wait in the hand-off: read until the gap shows.
  std::int64_t prev = before;
  bool gap_seen = false;
  for (int i = 0; i < 5 && !gap_seen; ++i) {
    if (rig.slot.view.index - prev == 4) gap_seen = true;
    prev = rig.slot.view.index;
    if (!gap_seen) {
      ASSERT_TRUE(rig.frame());
    }
  }
  EXPECT_TRUE(gap_seen) << "3 frames missing: the index jumps by 4";
  EXPECT_EQ(rig.source->health().sequence_gaps, 3u);
}

TEST(LibcameraSource, BackwardsTimestampIsCountedAndTheFrameGetsNoEstimate) {
  Rig rig;
  ASSERT_TRUE(rig.frame());
  rig.cam->timestamp_backwards = true;
  bool seen = false;
  for (int i = 0; i < 8 && !seen; ++i) {
    ASSERT_TRUE(rig.frame());
    seen = rig.slot.defect == core::RejectReason::time_backwards;
  }
  EXPECT_TRUE(seen);
  EXPECT_EQ(rig.source->health().timestamps_backwards, 1u);
  ASSERT_TRUE(rig.frame());
  EXPECT_FALSE(rig.slot.defect.has_value()) << "the next frame is good again";
}

TEST(LibcameraSource, MissingExposureMetadataIsNeverGuessed) {
  Rig rig;
  ASSERT_TRUE(rig.frame());
  rig.cam->omit_exposure = true;
  bool seen = false;
  for (int i = 0; i < 8 && !seen; ++i) {
    ASSERT_TRUE(rig.frame());
    seen = rig.slot.defect == core::RejectReason::no_exposure_metadata;
  }
  EXPECT_TRUE(seen);
  EXPECT_EQ(rig.source->health().no_exposure_metadata, 1u);
}

TEST(LibcameraSource, IncompleteBufferIsCountedAndNotDelivered) {
  Rig rig;
  ASSERT_TRUE(rig.frame());
  rig.cam->buffer_error = true;
  for (int i = 0; i < 4; ++i) ASSERT_TRUE(rig.frame());
  EXPECT_EQ(rig.source->health().requests_incomplete, 1u);
  EXPECT_EQ(rig.source->health().requeue_failures, 0u) << "its request is reused all the same";
}

TEST(LibcameraSource, UnpluggedCameraErrorsWithinStallPeriodsAndRecoversWhenBack) {
  Rig rig;
  for (int i = 0; i < 3; ++i) ASSERT_TRUE(rig.frame());
  rig.cam->present = false;
  // Frames already in the hand-off may still come; then errors.
  const std::int64_t unplugged = mono_now_ns();
  SourceStatus st = SourceStatus::frame;
  std::int64_t error_at = 0;
  for (int i = 0; i < 10 && st != SourceStatus::error; ++i) {
    st = rig.source->next(rig.slot, rig.stop);
    error_at = mono_now_ns();
  }
  ASSERT_EQ(st, SourceStatus::error);
  // 3 periods of 20 ms after the last frame + the frames queued at the unplug + 100 ms slack for a busy machine.
  EXPECT_LT(error_at - unplugged, (3 + 3) * 20 * kNsPerMs + 100 * kNsPerMs);
  std::this_thread::sleep_for(std::chrono::milliseconds(150));
  CameraHealth h = rig.source->health();
  EXPECT_EQ(h.disconnects, 1u);
  EXPECT_FALSE(h.streaming);
  EXPECT_NE(rig.source->health_text().find("DOWN"), std::string::npos);
  EXPECT_NE(rig.source->health_text().find("not present"), std::string::npos) << "the retry's error is shown";
  EXPECT_EQ(rig.source->next(rig.slot, rig.stop), SourceStatus::error) << "no frames while it is gone";

  rig.cam->present = true;
  ASSERT_TRUE(rig.frame(100)) << "the source re-opens the camera when it is back";
  h = rig.source->health();
  EXPECT_GE(h.restarts, 1u);
  EXPECT_LE(h.restarts, 3u) << "no restart loop once the camera is back";
  EXPECT_TRUE(h.streaming);
  EXPECT_GE(rig.cam->opens.load(), 2);
  const std::int64_t first_after = rig.slot.view.index;
  ASSERT_TRUE(rig.frame());
  EXPECT_GT(rig.slot.view.index, first_after) << "the index keeps rising across the restart";
}

TEST(LibcameraSource, SilentCameraIsRestarted) {
  Rig rig;
  ASSERT_TRUE(rig.frame());
  rig.cam->stalled = true;
  int errors = 0;
  const std::int64_t until = mono_now_ns() + 900 * kNsPerMs;
  while (mono_now_ns() < until) errors += rig.source->next(rig.slot, rig.stop) == SourceStatus::error ? 1 : 0;
  EXPECT_GE(errors, 3);
  EXPECT_GE(rig.cam->starts.load(), 2) << "a camera silent for retry_interval_ms is stopped and started again";
  // Stopping completed the requests still queued in the silent camera as cancelled.
  EXPECT_GE(rig.source->health().requests_cancelled, 3u);
  rig.cam->stalled = false;
  ASSERT_TRUE(rig.frame(100));
  EXPECT_GE(rig.source->health().frame_timeouts, 3u);
}

}  // namespace
}  // namespace gvs::drivers
