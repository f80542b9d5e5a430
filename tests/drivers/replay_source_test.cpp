// ReplaySource: a dataset longer than the decode-ahead window plays every
// frame in order with its own pixels, a frame the decoder cannot read goes
// out as a defect and is named once, and the source stops while its decoder
// waits for room.
#include <gtest/gtest.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <filesystem>
#include <thread>

#include <opencv2/core.hpp>

#include "gvs/drivers/dataset.hpp"
#include "gvs/drivers/frame_slot.hpp"
#include "gvs/drivers/replay_source.hpp"

namespace gvs::drivers {
namespace {

namespace fs = std::filesystem;

/// `frames` made-up 64x48 px frames at 250 fps (quick to play at pace; no
/// simulator, whose OpenCV worker threads TSan cannot see into).
fs::path write_dataset(const std::string& name, int frames) {
  const fs::path dir = fs::temp_directory_path() / ("gvs_replay_" + name + "_" + std::to_string(getpid()));
  fs::remove_all(dir);
  CameraInfo cam;
  cam.geometry.width_px = 64;
  cam.geometry.height_px = 48;
  DatasetWriter writer(dir, cam, false);
  for (int i = 0; i < frames; ++i) {
    cv::Mat gray(48, 64, CV_8UC1);
    for (int r = 0; r < gray.rows; ++r) {
      for (int c = 0; c < gray.cols; ++c) gray.at<std::uint8_t>(r, c) = static_cast<std::uint8_t>((r * 7 + c * 3 + i * 11) % 251);
    }
    FrameRecord record;
    record.index = i;
    record.t_ns = static_cast<std::int64_t>(i) * 4'000'000;
    record.exposure.exposure_us = 100.0;
    writer.write_frame(gray, record);
  }
  return dir;
}

constexpr double kFourFramesMb = 4 * 64 * 48 / 1048576.0;

TEST(ReplaySource, PlaysADatasetLongerThanItsWindowFrameByFrame) {
  const fs::path dir = write_dataset("long", 40);
  const DatasetReader reader(dir);
  ReplaySource source(dir, kFourFramesMb);
  EXPECT_EQ(source.window_frames(), 4u) << "the memory held is the window's, not the dataset's";
  FrameSlot slot;
  source.prepare(slot);
  std::atomic<bool> stop{false};
  for (std::size_t i = 0; i < reader.frames().size(); ++i) {
    ASSERT_EQ(source.next(slot, stop), SourceStatus::frame) << "frame " << i;
    EXPECT_FALSE(slot.defect.has_value());
    EXPECT_EQ(slot.view.index, reader.frames()[i].index);
    EXPECT_EQ(cv::norm(slot.view.gray, reader.load_gray(i), cv::NORM_INF), 0.0) << "frame " << i << "'s pixels";
  }
  EXPECT_EQ(source.next(slot, stop), SourceStatus::end);
  EXPECT_TRUE(source.take_log_lines().empty());
  fs::remove_all(dir);
}

TEST(ReplaySource, AFrameTheDecoderCannotReadGoesOutAsADefectAndIsNamedOnce) {
  const fs::path dir = write_dataset("broken", 20);
  const DatasetReader reader(dir);
  fs::resize_file(dir / reader.frames()[12].file, 40);  // beyond the first window: found by the decoder thread
  ReplaySource source(dir, kFourFramesMb);
  FrameSlot slot;
  source.prepare(slot);
  std::atomic<bool> stop{false};
  int defects = 0;
  for (std::size_t i = 0; i < reader.frames().size(); ++i) {
    ASSERT_EQ(source.next(slot, stop), SourceStatus::frame);
    if (slot.defect) {
      ++defects;
      EXPECT_EQ(i, 12u);
      EXPECT_EQ(*slot.defect, core::RejectReason::unreadable);
    }
  }
  EXPECT_EQ(defects, 1);
  const std::vector<std::string> lines = source.take_log_lines();
  ASSERT_EQ(lines.size(), 1u);
  EXPECT_NE(lines[0].find("frame " + std::to_string(reader.frames()[12].index) + " gets no estimate"),
            std::string::npos)
      << lines[0];
  EXPECT_TRUE(source.take_log_lines().empty()) << "each line once";
  fs::remove_all(dir);
}

TEST(ReplaySource, StopsWhileItsDecoderWaitsForRoom) {
  const fs::path dir = write_dataset("stop", 30);
  const auto t0 = std::chrono::steady_clock::now();
  {
    ReplaySource source(dir, kFourFramesMb);  // nothing consumed: the decoder waits for a free slot
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  EXPECT_LT(std::chrono::steady_clock::now() - t0, std::chrono::seconds(5));
  fs::remove_all(dir);
}

TEST(ReplaySource, RefusesADatasetWhoseFirstWindowCannotBeRead) {
  const fs::path dir = write_dataset("unreadable", 6);
  const DatasetReader reader(dir);
  for (const FrameRecord& r : reader.frames()) fs::resize_file(dir / r.file, 40);
  try {
    ReplaySource source(dir, kFourFramesMb);
    ADD_FAILURE() << "a dataset with no readable frame accepted";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(dir.string()), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("could be read"), std::string::npos) << e.what();
  }
  fs::remove_all(dir);
}

}  // namespace
}  // namespace gvs::drivers
