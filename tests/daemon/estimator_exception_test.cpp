// An estimator that throws (OpenCV's cv::Exception, or any std::exception)
// must cost one frame, never the daemon: FrameEstimator::estimate catches,
// returns no estimate, counts it and resets; the pipeline keeps running and
// counts the frame as an estimator failure.
#include <gtest/gtest.h>
#include <unistd.h>

#include <atomic>
#include <filesystem>
#include <stdexcept>
#include <thread>

#include <opencv2/core.hpp>

#include "gvs/can/sink.hpp"
#include "gvs/drivers/clock.hpp"
#include "gvs/daemon/pipeline.hpp"
#include "gvsd_test_support.hpp"
#include "steady_camera.hpp"

namespace gvs::daemon {
namespace {

/// The source's truth, except that frames with index in [from, to] make
/// OpenCV throw (adding matrices of different sizes), and frames with index
/// `std_throw_at` throw a std::runtime_error.
class ThrowingEstimator final : public FrameEstimator {
 public:
  ThrowingEstimator(std::int64_t from, std::int64_t to, std::int64_t std_throw_at)
      : from_(from), to_(to), std_throw_at_(std_throw_at), inner_(make_frame_estimator("truth", {})) {}
  core::VelocityEstimate estimate_frame(const drivers::FrameSlot& slot) override {
    const std::int64_t i = slot.view.index;
    if (i >= from_ && i <= to_) {
      cv::Mat a(4, 4, CV_8UC1, cv::Scalar(1)), b(3, 3, CV_8UC1, cv::Scalar(1)), sum;
      cv::add(a, b, sum);  // throws cv::Exception: sizes differ
    }
    if (i == std_throw_at_) throw std::runtime_error("not a cv::Exception");
    return inner_->estimate(slot);
  }
  void reset() noexcept override { resets.fetch_add(1); }
  std::string name() const override { return "throwing"; }

  std::atomic<int> resets{0};

 private:
  std::int64_t from_, to_, std_throw_at_;
  std::unique_ptr<FrameEstimator> inner_;
};

drivers::FrameSlot slot_with(std::int64_t index, std::int64_t t_ns, double exposure_us) {
  drivers::FrameSlot s;
  s.view.index = index;
  s.view.t_ns = t_ns;
  s.view.exposure.exposure_us = exposure_us;
  s.truth = drivers::FrameTruth{true, 10.0, 0.0, 10.0, 0.0, 0.0};
  return s;
}

TEST(EstimatorException, CvExceptionBecomesNoEstimateCountedAndReset) {
  ThrowingEstimator est(3, 3, -1);
  const core::VelocityEstimate before = est.estimate(slot_with(2, 1'000'000'000, 1000.0));
  EXPECT_TRUE(before.has_speed);
  const int resets_before = est.resets.load();

  const core::VelocityEstimate e = est.estimate(slot_with(3, 2'000'000'000, 1000.0));
  EXPECT_FALSE(e.has_speed);
  EXPECT_FALSE(e.has_direction);
  EXPECT_EQ(e.quality, 0.0);
  EXPECT_EQ(e.method, core::Method::estimator_exception);
  EXPECT_EQ(e.index, 3);
  EXPECT_EQ(e.t_ns, 2'000'500'000) << "the failure still names the frame's mid-exposure";
  EXPECT_EQ(est.estimator_exceptions(), 1u);
  EXPECT_EQ(est.resets.load(), resets_before + 1) << "a half-updated history must not measure the next frame";

  const core::VelocityEstimate after = est.estimate(slot_with(4, 3'000'000'000, 1000.0));
  EXPECT_TRUE(after.has_speed) << "the next frame is estimated as usual";
  EXPECT_EQ(est.estimator_exceptions(), 1u);
}

TEST(EstimatorException, AnyStdExceptionIsCaught) {
  ThrowingEstimator est(-1, -1, 5);
  const core::VelocityEstimate e = est.estimate(slot_with(5, 0, 500.0));
  EXPECT_FALSE(e.has_speed);
  EXPECT_EQ(e.method, core::Method::estimator_exception);
  EXPECT_EQ(est.estimator_exceptions(), 1u);
}

TEST(EstimatorException, PipelineKeepsRunningAndCountsTheFailures) {
  const std::string log = (std::filesystem::temp_directory_path() /
                           ("gvsd_estimator_exception_" + std::to_string(getpid()) + ".log")).string();
  const DaemonConfig c = testing::unprivileged_config();
  // Frames 10..14 throw: without the catch, std::terminate ends the test program here.
  auto estimator = std::make_unique<ThrowingEstimator>(10, 14, -1);
  const ThrowingEstimator* est = estimator.get();
  Pipeline p(c, std::make_unique<testing::SteadyCamera>(), std::move(estimator), can::open_sink("candump:" + log));
  p.start();
  const std::int64_t t0 = drivers::mono_now_ns();
  while (p.latest().estimate.index < 40 && drivers::mono_now_ns() - t0 < 10 * drivers::kNsPerS) {
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  p.request_stop();
  p.join();
  const auto msgs = testing::read_candump_log(log);
  std::filesystem::remove(log);

  ASSERT_GE(p.latest().estimate.index, 40) << "frames after the exceptions were processed";
  EXPECT_TRUE(p.latest().estimate.has_speed);
  // The processing thread may skip some of frames 10..14 (it takes the newest).
  const std::uint64_t thrown = est->estimator_exceptions();
  EXPECT_GE(thrown, 1u);
  EXPECT_LE(thrown, 5u);
  EXPECT_EQ(p.counters().estimator_failures.load(), thrown) << "each exception is an estimator failure";
  int valid = 0;
  for (const auto& m : msgs.velocity) valid += m.decoded.velocity.speed_valid ? 1 : 0;
  EXPECT_GE(valid, 5) << "valid velocity keeps going out after the exceptions";
}

/// The source's truth with the speed taken out of frames 10..19: a
/// direction without a speed, as a streak too long to measure gives.
class DirectionOnlyEstimator final : public FrameEstimator {
 public:
  DirectionOnlyEstimator() : inner_(make_frame_estimator("truth", {})) {}
  core::VelocityEstimate estimate_frame(const drivers::FrameSlot& slot) override {
    core::VelocityEstimate e = inner_->estimate(slot);
    if (slot.view.index >= 10 && slot.view.index <= 19) {
      e.has_speed = false;
      e.method = core::Method::streak_cont;
    }
    return e;
  }
  void reset() noexcept override {}
  std::string name() const override { return "direction-only"; }

 private:
  std::unique_ptr<FrameEstimator> inner_;
};

TEST(EstimatorFailures, ADirectionWithoutSpeedIsCountedApartFromNoEstimate) {
  const std::string log = (std::filesystem::temp_directory_path() /
                           ("gvsd_direction_only_" + std::to_string(getpid()) + ".log")).string();
  Pipeline p(testing::unprivileged_config(), std::make_unique<testing::SteadyCamera>(),
             std::make_unique<DirectionOnlyEstimator>(), can::open_sink("candump:" + log));
  p.start();
  const std::int64_t t0 = drivers::mono_now_ns();
  while (p.latest().estimate.index < 30 && drivers::mono_now_ns() - t0 < 10 * drivers::kNsPerS) {
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  p.request_stop();
  p.join();
  std::filesystem::remove(log);
  ASSERT_GE(p.latest().estimate.index, 30);
  // The processing thread may skip frames (it takes the newest), not all ten.
  EXPECT_GE(p.counters().direction_only.load(), 1u);
  EXPECT_LE(p.counters().direction_only.load(), 10u);
  EXPECT_EQ(p.counters().estimator_failures.load(), 0u) << "every frame had an estimate";
}

}  // namespace
}  // namespace gvs::daemon
