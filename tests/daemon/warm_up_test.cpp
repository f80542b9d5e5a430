// The estimator's warm-up before the first real frame (warm_up.hpp): its
// made-up frames take the gvs estimator down each path the car's frames take,
// and leave nothing behind in its history.
#include <gtest/gtest.h>

#include <set>
#include <string>

#include "gvs/core/method.hpp"
#include "gvs/daemon/frame_estimator.hpp"
#include "gvs/daemon/warm_up.hpp"

namespace gvs::daemon {
namespace {

/// A slot as FrameSource::prepare leaves it: a grey image of the camera's size.
drivers::FrameSlot prepared_slot(const core::CameraGeometry& camera) {
  drivers::FrameSlot slot;
  slot.view.gray.create(camera.height_px, camera.width_px, CV_8UC1);
  return slot;
}

TEST(WarmUp, FramesTakeTheEstimatorThroughEachKindOfFrame) {
  const core::CameraGeometry camera;
  WarmUpFrames frames(camera);
  drivers::FrameSlot slot = prepared_slot(camera);
  const std::unique_ptr<FrameEstimator> estimator = make_frame_estimator("gvs", camera, {});
  std::set<std::string> methods;
  for (std::size_t i = 0; i < frames.size(); ++i) {
    frames.draw(i, slot);
    methods.insert(core::method_word(estimator->estimate(slot).method));
  }
  std::string seen;
  for (const std::string& m : methods) seen += m + " ";
  EXPECT_TRUE(methods.count("pair")) << seen;
  EXPECT_TRUE(methods.count("blur-cont")) << "the 3 ms streaks, tracked: " << seen;
  EXPECT_TRUE(methods.count("dpiv-cont")) << seen;
}

TEST(WarmUp, LeavesNothingInTheEstimatorsHistory) {
  const core::CameraGeometry camera;
  WarmUpFrames frames(camera);
  drivers::FrameSlot f = prepared_slot(camera);
  const std::unique_ptr<FrameEstimator> warmed = make_frame_estimator("gvs", camera, {});
  const std::unique_ptr<FrameEstimator> fresh = make_frame_estimator("gvs", camera, {});
  warm_up(*warmed, frames, f);
  // The same frames again, 10 s later: a warmed estimator must see them as
  // a fresh one does (the first of them without a previous frame).
  for (std::size_t i = 0; i < frames.size(); ++i) {
    frames.draw(i, f);
    f.view.t_ns += 10'000'000'000;
    const core::VelocityEstimate a = warmed->estimate(f);
    const core::VelocityEstimate b = fresh->estimate(f);
    EXPECT_EQ(core::method_word(a.method), core::method_word(b.method)) << "frame " << f.view.index;
    EXPECT_EQ(a.has_speed, b.has_speed) << "frame " << f.view.index;
    EXPECT_EQ(a.speed_mps, b.speed_mps) << "frame " << f.view.index;
    EXPECT_EQ(a.direction_deg, b.direction_deg) << "frame " << f.view.index;
    EXPECT_EQ(a.quality, b.quality) << "frame " << f.view.index;
  }
  EXPECT_EQ(warmed->rejected_frames(), fresh->rejected_frames());
}

}  // namespace
}  // namespace gvs::daemon
