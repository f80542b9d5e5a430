// The libcamera source's frame path on the fake camera: a frame's pixels are
// copied once, by next(), out of the camera's own buffer, which goes back to
// the camera only after that copy; stopping or restarting the camera with
// frames handed over and not yet copied never reads a freed buffer (the fake
// frees its buffers on close: ASan) nor one given back (TSan).
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <functional>
#include <thread>

#include "gvs/drivers/clock.hpp"
#include "libcamera_rig.hpp"

namespace gvs::drivers {
namespace {

using testing::fake_pattern_intact;
using testing::LibcameraRig;
using testing::small_settings;

/// Polls `done` every 5 ms for up to `timeout_ms`.
bool eventually(const std::function<bool()>& done, int timeout_ms = 3000) {
  const std::int64_t until = mono_now_ns() + timeout_ms * kNsPerMs;
  while (!done()) {
    if (mono_now_ns() > until) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  return true;
}

TEST(LibcameraSource, FramesWaitInTheCameraBuffersAndNextCopiesEachOnce) {
  LibcameraRig rig;  // 3 buffers: the capture side holds at most 2
  std::this_thread::sleep_for(std::chrono::milliseconds(200));  // 10 frame periods, nobody asks
  CameraHealth h = rig.source->health();
  EXPECT_EQ(h.frames_copied, 0u) << "the camera thread copies nothing";
  EXPECT_EQ(h.frames_delivered, 2u) << "two requests handed over, their pixels still in the camera's buffers";
  EXPECT_GE(h.handoff_full, 5u) << "the other frames' requests re-queued unread: one request always queued";
  // With the app: the two handed-over buffers, and for a moment a third,
  // just completed, until the source gives it back unread. Never fewer:
  // a handed-over buffer is not queued again before its copy.
  int fewest = 3;
  for (int i = 0; i < 20; ++i) {
    fewest = std::min(fewest, rig.cam->with_app.load());
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  EXPECT_EQ(fewest, 2) << "a handed-over buffer is not queued again before its copy";

  constexpr int kFrames = 12;
  for (int i = 0; i < kFrames; ++i) {
    ASSERT_TRUE(rig.frame());
    // Sequence = index on the first stream: the frame's own pixels, none of a re-queued buffer.
    const auto seq = static_cast<int>(rig.slot.view.index);
    ASSERT_EQ(rig.slot.view.gray.at<std::uint8_t>(0, 0), seq & 0x7F) << "frame " << i;
    ASSERT_TRUE(fake_pattern_intact(rig.slot)) << "frame " << i;
  }
  h = rig.source->health();
  EXPECT_EQ(h.frames_copied, static_cast<std::uint64_t>(kFrames)) << "one copy per frame delivered";
  EXPECT_EQ(h.stale_frames, 0u);
  EXPECT_EQ(h.requeue_failures, 0u);
  EXPECT_NE(rig.source->health_text().find("copied 12,"), std::string::npos) << rig.source->health_text();
  // Each copied buffer goes back: frames keep coming with 3 buffers.
  for (int i = 0; i < kFrames; ++i) ASSERT_TRUE(rig.frame());
}

TEST(LibcameraSource, StopsCleanlyWithFramesHandedOverAndNotCopied) {
  for (int round = 0; round < 3; ++round) {
    LibcameraRig rig;
    ASSERT_TRUE(rig.frame());
    ASSERT_TRUE(eventually([&] {
      const CameraHealth h = rig.source->health();
      return h.frames_delivered - h.frames_copied == 2;
    })) << "two frames wait in the camera's buffers";
    rig.source.reset();  // stops and closes (frees) the camera's buffers under them
    EXPECT_EQ(rig.cam->with_app.load(), 0);
  }
}

TEST(LibcameraSource, FramesWaitingAcrossARestartAreDroppedUnread) {
  LibcameraRig rig;
  ASSERT_TRUE(rig.frame());
  ASSERT_TRUE(eventually([&] {
    const CameraHealth h = rig.source->health();
    return h.frames_delivered - h.frames_copied == 2;
  }));
  // Unplugged: the supervisor stops and closes the camera, freeing the two
  // buffers the waiting frames point into.
  rig.cam->present = false;
  ASSERT_TRUE(eventually([&] { return rig.source->health_text().find("not present") != std::string::npos; }));
  rig.cam->present = true;
  ASSERT_TRUE(eventually([&] { return rig.source->health().restarts >= 1; }));

  ASSERT_TRUE(rig.frame(100));
  EXPECT_TRUE(fake_pattern_intact(rig.slot)) << "a frame of the new stream";
  const CameraHealth h = rig.source->health();
  EXPECT_EQ(h.stale_frames, 2u) << "the frames of the closed stream were dropped, not read";
  EXPECT_EQ(h.frames_copied, 2u);
}

TEST(LibcameraSource, RestartsWhileTheCaptureThreadCopiesAreClean) {
  LibcameraSettings s = small_settings();
  s.retry_interval_ms = 100.0;
  LibcameraRig rig(s);
  std::atomic<int> frames{0};
  std::atomic<bool> torn{false};
  std::thread capture([&] {
    while (!rig.stop.load()) {
      if (rig.source->next(rig.slot, rig.stop) != SourceStatus::frame) continue;
      if (!fake_pattern_intact(rig.slot)) torn = true;
      ++frames;
    }
  });
  const auto more_frames = [&] {
    const int from = frames.load();
    return eventually([&] { return frames.load() >= from + 3; });
  };
  for (int cycle = 0; cycle < 3; ++cycle) {
    ASSERT_TRUE(more_frames()) << "cycle " << cycle;
    const CameraHealth before = rig.source->health();
    rig.cam->present = false;
    EXPECT_TRUE(eventually([&] { return rig.source->health().disconnects > before.disconnects; }));
    rig.cam->present = true;
    EXPECT_TRUE(eventually([&] { return rig.source->health().restarts > before.restarts; }));
  }
  EXPECT_TRUE(more_frames()) << "frames after the last restart";
  rig.stop = true;
  capture.join();
  EXPECT_FALSE(torn.load()) << "a frame with bytes of a re-queued buffer";
  EXPECT_EQ(rig.source->health().frames_copied, static_cast<std::uint64_t>(frames.load()));
  rig.source.reset();
}

}  // namespace
}  // namespace gvs::drivers
