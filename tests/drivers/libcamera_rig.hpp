// The libcamera source on a fake camera, as the source tests drive it: the
// test thread plays the capture thread.
#pragma once

#include <atomic>
#include <memory>

#include "fake_camera_device.hpp"
#include "gvs/drivers/libcamera_source.hpp"

namespace gvs::drivers::testing {

/// 64x48 at 50 fps, 3 buffers.
inline LibcameraSettings small_settings() {
  LibcameraSettings s;
  s.camera = {64, 48, 0.1, 0.0};
  s.fps = 50.0;
  s.buffer_count = 3;
  s.exposure_initial_us = 1000.0;
  s.exposure_max_us = 3000.0;
  s.retry_interval_ms = 300.0;  // long enough that a loaded 2-core machine does not look like a silent camera
  return s;
}

struct LibcameraRig {
  std::shared_ptr<FakeCamera> cam = std::make_shared<FakeCamera>();
  std::unique_ptr<LibcameraSource> source;
  FrameSlot slot;
  std::atomic<bool> stop{false};

  explicit LibcameraRig(const LibcameraSettings& s = small_settings()) {
    source = std::make_unique<LibcameraSource>(std::make_unique<FakeCameraDevice>(cam), s);
    source->prepare(slot);
  }
  /// The next frame (skipping errors) within `tries` calls.
  bool frame(int tries = 20) {
    for (int i = 0; i < tries; ++i) {
      if (source->next(slot, stop) == SourceStatus::frame) return true;
    }
    return false;
  }
};

/// The fake's pattern, (x + 3 y + sequence) & 0x7F, whole: no byte of a
/// re-queued buffer (0xEE) and no torn frame.
inline bool fake_pattern_intact(const FrameSlot& slot) {
  const int base = slot.view.gray.at<std::uint8_t>(0, 0);
  for (int y = 0; y < slot.view.gray.rows; ++y) {
    for (int x = 0; x < slot.view.gray.cols; ++x) {
      if (slot.view.gray.at<std::uint8_t>(y, x) != ((x + 3 * y + base) & 0x7F)) return false;
    }
  }
  return true;
}

}  // namespace gvs::drivers::testing
