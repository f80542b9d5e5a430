// Every part of the frame path stamps a frame with core::mid_exposure_ns:
// the truth estimator, the frame checks and the exception boundary give the
// same instant to the nanosecond, rounded, never truncated.
#include <gtest/gtest.h>

#include "gvs/daemon/frame_estimator.hpp"
#include "gvs/dsp/frame_processor.hpp"

namespace gvs::daemon {
namespace {

/// A frame whose mid-exposure falls 0.98 ns past a whole nanosecond
/// (1000 + 2^-9 us of exposure, exact in binary): truncating loses it.
drivers::FrameSlot awkward_slot() {
  drivers::FrameSlot s;
  s.view.index = 12;
  s.view.t_ns = 5'000'000'000;
  s.view.exposure.exposure_us = 1000.0 + 1.0 / 512.0;
  s.truth = drivers::FrameTruth{true, 10.0, 0.0, 10.0, 0.0, 0.0};
  return s;
}

TEST(FrameTime, TruthEstimatorStampsTheRoundedMidExposure) {
  const drivers::FrameSlot s = awkward_slot();
  const std::int64_t want = core::mid_exposure_ns(s.view.t_ns, s.view.exposure);
  ASSERT_EQ(want, 5'000'500'001);
  auto truth = make_frame_estimator("truth", {});
  EXPECT_EQ(truth->estimate(s).t_ns, want);
  drivers::FrameSlot unknown = s;
  unknown.truth.known = false;
  EXPECT_EQ(truth->estimate(unknown).t_ns, want) << "the no-estimate answer too";
}

TEST(FrameTime, FrameChecksStampTheRoundedMidExposure) {
  const drivers::FrameSlot s = awkward_slot();
  const std::int64_t want = core::mid_exposure_ns(s.view.t_ns, s.view.exposure);
  dsp::FrameProcessorConfig config;
  config.estimator.method = "gvs";
  dsp::FrameProcessor p(config);
  EXPECT_EQ(p.process(s.view).t_ns, want) << "wrong-size (no pixels)";
  EXPECT_EQ(p.reject(s.view, core::RejectReason::unreadable).t_ns, want);
}

}  // namespace
}  // namespace gvs::daemon
