// The three gvsd threads in-process with a scripted camera: stale estimates
// go out invalid, overruns are counted and reported, exposure control closes
// the loop, a bounded run sends exactly its periods, stop is prompt.
// Threaded: run under TSan and ASan too.
#include <gtest/gtest.h>
#include <unistd.h>

#include <atomic>
#include <filesystem>
#include <thread>

#include "gvs/can/e2e.hpp"
#include "gvs/can/sink.hpp"
#include "gvs/drivers/clock.hpp"
#include "gvs/daemon/pipeline.hpp"
#include "gvsd_test_support.hpp"
#include "scripted_camera.hpp"

namespace gvs::daemon {
namespace {

using testing::read_candump_log;
using testing::ScriptedCamera;


/// An estimator that takes `delay_ms` per frame and reports the truth.
class SlowEstimator final : public FrameEstimator {
 public:
  explicit SlowEstimator(int delay_ms) : delay_ms_(delay_ms), inner_(make_frame_estimator("truth", {})) {}
  core::VelocityEstimate estimate_frame(const drivers::FrameSlot& slot) override {
    drivers::sleep_until_ns(drivers::mono_now_ns() + delay_ms_ * drivers::kNsPerMs);
    return inner_->estimate(slot);
  }
  void reset() noexcept override {}
  std::string name() const override { return "slow"; }

 private:
  int delay_ms_;
  std::unique_ptr<FrameEstimator> inner_;
};

/// The source's truth (10 m/s, 2 deg) with quality `quality`, and a false
/// standstill on the frames with index in [outlier_from, outlier_to].
class DoctoredTruth final : public FrameEstimator {
 public:
  DoctoredTruth(double quality, std::int64_t outlier_from, std::int64_t outlier_to)
      : quality_(quality), from_(outlier_from), to_(outlier_to), inner_(make_frame_estimator("truth", {})) {}
  core::VelocityEstimate estimate_frame(const drivers::FrameSlot& slot) override {
    core::VelocityEstimate e = inner_->estimate(slot);
    e.quality = quality_;
    if (slot.view.index >= from_ && slot.view.index <= to_) {
      e.speed_mps = e.vx_mps = e.vy_mps = e.direction_deg = 0.0;
      e.has_direction = false;
    }
    return e;
  }
  void reset() noexcept override {}
  std::string name() const override { return "doctored"; }

 private:
  double quality_;
  std::int64_t from_, to_;
  std::unique_ptr<FrameEstimator> inner_;
};

DaemonConfig test_config() {
  DaemonConfig c;
  c.capture_thread.priority = 0;  // the tests must not take the shared machine's CPUs
  c.processing_thread.priority = 0;
  c.sender_thread.priority = 0;
  c.prefault_stack_kb = 64;
  return c;
}

std::string temp_log(const char* name) {
  return (std::filesystem::temp_directory_path() /
          ("gvsd_pipeline_" + std::string(name) + "_" + std::to_string(getpid()) + ".log"))
      .string();
}

TEST(Pipeline, StaleEstimateGoesOutInvalidNeverAsFresh) {
  const std::string log = temp_log("stale");
  DaemonConfig c = test_config();
  auto camera = std::make_unique<ScriptedCamera>(100.0, 30);  // 300 ms of frames, then silence
  ScriptedCamera* cam = camera.get();
  Pipeline p(c, std::move(camera), make_frame_estimator("truth", {}), can::open_sink("candump:" + log));
  p.start();
  while (cam->silent_since_ns.load() < 0) std::this_thread::sleep_for(std::chrono::milliseconds(5));
  const std::int64_t silent_mono = cam->silent_since_ns.load();
  const std::int64_t silent_real = drivers::real_now_ns() - (drivers::mono_now_ns() - silent_mono);
  std::this_thread::sleep_for(std::chrono::milliseconds(400));
  p.request_stop();
  p.join();

  const auto msgs = read_candump_log(log);
  std::filesystem::remove(log);
  ASSERT_GT(msgs.velocity.size(), 25u);
  int fresh_valid = 0, late_checked = 0, late_valid = 0;
  for (std::size_t i = 0; i < msgs.velocity.size(); ++i) {
    const auto& m = msgs.velocity[i];
    const auto& xy = msgs.velocity_xy[i].decoded.xy;
    if (m.t_ns < silent_real - 20 * drivers::kNsPerMs && m.t_ns > silent_real - 250 * drivers::kNsPerMs) {
      fresh_valid += m.decoded.velocity.valid ? 1 : 0;
      if (m.decoded.velocity.valid) {
        EXPECT_NEAR(m.decoded.velocity.speed_mps, 10.0, 0.01);
        EXPECT_NEAR(m.decoded.velocity.direction_deg, 2.0, 0.01);
        EXPECT_LE(xy.age_ms, 50u);
      }
    }
    // 50 ms staleness limit + the last frame's age at the silence + one period of slack.
    if (m.t_ns > silent_real + 80 * drivers::kNsPerMs) {
      ++late_checked;
      late_valid += m.decoded.velocity.valid || m.decoded.velocity.speed_valid || xy.valid ? 1 : 0;
      EXPECT_GT(xy.age_ms, 50u) << "the age says how old the estimate is";
    }
  }
  EXPECT_GE(fresh_valid, 8) << "while frames flow, estimates go out valid";
  EXPECT_GE(late_checked, 10);
  EXPECT_EQ(late_valid, 0) << "an estimate older than the limit must never go out as fresh";
  ASSERT_FALSE(msgs.status.empty());
  const auto& last_status = msgs.status.back().decoded.status_msg;
  EXPECT_EQ(last_status.state, can::SensorState::Stopping);
  const auto& before = msgs.status[msgs.status.size() - 2].decoded.status_msg;
  EXPECT_NE(before.faults & can::kFaultEstimateStale, 0) << "status flags the stale estimate";
  EXPECT_NE(before.faults & can::kFaultCamera, 0) << "status flags the silent camera";
  EXPECT_EQ(before.state, can::SensorState::Fault);
  EXPECT_EQ(msgs.bad_crc, 0u);
  EXPECT_GT(p.counters().invalid_sent.load(), 10u);
}

TEST(Pipeline, LowQualityEstimatesGoOutInvalidWithTheirQualityAndAge) {
  const std::string log = temp_log("lowq");
  DaemonConfig c = test_config();  // [can] min_quality 0.3 by default
  Pipeline p(c, std::make_unique<ScriptedCamera>(100.0, 1000000), std::make_unique<DoctoredTruth>(0.1, -1, -1),
             can::open_sink("candump:" + log));
  p.start();
  std::this_thread::sleep_for(std::chrono::milliseconds(400));
  p.request_stop();
  p.join();
  const auto msgs = read_candump_log(log);
  std::filesystem::remove(log);
  ASSERT_GT(msgs.velocity.size(), 10u);
  int fresh_low_quality = 0;
  for (std::size_t i = 0; i < msgs.velocity.size(); ++i) {
    const auto& v = msgs.velocity[i].decoded.velocity;
    const auto& xy = msgs.velocity_xy[i].decoded.xy;
    EXPECT_FALSE(v.valid || v.speed_valid || v.direction_valid || v.yaw_rate_valid || xy.valid)
        << "a quality 0.1 estimate went out valid in message " << i;
    EXPECT_EQ(v.speed_mps, 0.0);
    EXPECT_EQ(xy.vx_mps, 0.0);
    if (v.quality_pct == 10.0 && xy.age_ms <= 50) ++fresh_low_quality;
  }
  EXPECT_GE(fresh_low_quality, 8) << "GVS_Quality and GVS_Age still say what was measured and when";
  ASSERT_GE(msgs.status.size(), 3u);
  const auto& s = msgs.status[msgs.status.size() - 2].decoded.status_msg;
  EXPECT_EQ(s.faults & can::kFaultEstimateStale, 0) << "doubtful is not stale";
  EXPECT_EQ(s.state, can::SensorState::Degraded);
  EXPECT_EQ(p.counters().implausible_estimates.load(), 0u) << "the gate does not judge what goes out invalid anyway";
}

TEST(Pipeline, QualityAtTheThresholdGoesOutValid) {
  const std::string log = temp_log("atq");
  DaemonConfig c = test_config();
  c.min_quality = 0.35;
  Pipeline p(c, std::make_unique<ScriptedCamera>(100.0, 1000000), std::make_unique<DoctoredTruth>(0.35, -1, -1),
             can::open_sink("candump:" + log));
  p.start();
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  p.request_stop();
  p.join();
  const auto msgs = read_candump_log(log);
  std::filesystem::remove(log);
  int valid = 0;
  for (const auto& m : msgs.velocity) {
    if (!m.decoded.velocity.valid) continue;
    ++valid;
    EXPECT_NEAR(m.decoded.velocity.speed_mps, 10.0, 0.01);
    EXPECT_EQ(m.decoded.velocity.quality_pct, 35.0);
  }
  EXPECT_GE(valid, 8);
}

TEST(Pipeline, MinQualityReloadsWhileRunning) {
  const std::string log = temp_log("reloadq");
  DaemonConfig c = test_config();  // min_quality 0.3: quality 0.25 goes out invalid
  Pipeline p(c, std::make_unique<ScriptedCamera>(100.0, 1000000), std::make_unique<DoctoredTruth>(0.25, -1, -1),
             can::open_sink("candump:" + log));
  p.start();
  std::this_thread::sleep_for(std::chrono::milliseconds(250));
  const std::int64_t reload_real = drivers::real_now_ns();
  c.min_quality = 0.2;
  p.apply_reloadable(c);  // what SIGHUP does
  std::this_thread::sleep_for(std::chrono::milliseconds(250));
  p.request_stop();
  p.join();
  const auto msgs = read_candump_log(log);
  std::filesystem::remove(log);
  int valid_before = 0, valid_after = 0, after = 0;
  for (const auto& m : msgs.velocity) {
    if (m.t_ns < reload_real) valid_before += m.decoded.velocity.valid ? 1 : 0;
    if (m.t_ns > reload_real + 25 * drivers::kNsPerMs) {
      ++after;
      valid_after += m.decoded.velocity.valid ? 1 : 0;
    }
  }
  EXPECT_EQ(valid_before, 0) << "quality 0.25 < 0.3";
  EXPECT_GE(after, 8);
  EXPECT_EQ(valid_after, after) << "after the reload quality 0.25 >= 0.2";
}

TEST(Pipeline, ImplausibleStandstillIsHeldBackCountedAndFlagged) {
  const std::string log = temp_log("implausible");
  DaemonConfig c = test_config();
  // 10 m/s at 50 fps; frames 20..22 read a standstill (36 km/h -> 0 in 20 ms).
  auto camera = std::make_unique<ScriptedCamera>(50.0, 1000000);
  Pipeline p(c, std::move(camera), std::make_unique<DoctoredTruth>(1.0, 20, 22), can::open_sink("candump:" + log));
  p.start();
  std::this_thread::sleep_for(std::chrono::milliseconds(900));
  p.request_stop();
  p.join();
  const auto msgs = read_candump_log(log);
  std::filesystem::remove(log);

  const std::uint64_t held_back = p.counters().implausible_estimates.load();
  EXPECT_GE(held_back, 1u);
  EXPECT_LE(held_back, 3u) << "only the three false frames";
  int fresh_held_back = 0, valid_after = 0;
  bool seen_held_back = false;
  for (std::size_t i = 0; i < msgs.velocity.size(); ++i) {
    const auto& v = msgs.velocity[i].decoded.velocity;
    const auto& xy = msgs.velocity_xy[i].decoded.xy;
    if (v.speed_valid) {
      EXPECT_NEAR(v.speed_mps, 10.0, 0.01) << "the false standstill never goes out as valid (message " << i << ")";
      if (seen_held_back) ++valid_after;
    } else if (v.quality_pct == 100.0 && xy.age_ms <= 50) {
      ++fresh_held_back;  // a fresh, quality-1 estimate sent invalid: held back by the gate
      seen_held_back = true;
      EXPECT_FALSE(v.valid || v.direction_valid || v.yaw_rate_valid || xy.valid);
    }
  }
  EXPECT_GE(fresh_held_back, 1) << "the held-back estimate goes out with every Valid bit 0";
  EXPECT_GE(valid_after, 5) << "the real speed goes out valid again";
  ASSERT_GE(msgs.status.size(), 5u);
  int flagged = 0;
  for (std::size_t i = 0; i + 1 < msgs.status.size(); ++i) {  // the last one is Stopping
    if ((msgs.status[i].decoded.status_msg.faults & can::kFaultImplausible) != 0) ++flagged;
  }
  EXPECT_GE(flagged, 1) << "GVS_FaultImplausible in the next status";
  EXPECT_LE(flagged, 2) << "only in the status periods that held one back";
  EXPECT_EQ(msgs.status[0].decoded.status_msg.faults & can::kFaultImplausible, 0);
}

TEST(Pipeline, SlowProcessingCountsOverrunsAndSkipsToTheNewestFrame) {
  const std::string log = temp_log("overrun");
  DaemonConfig c = test_config();
  c.ring_slots = 2;
  Pipeline p(c, std::make_unique<ScriptedCamera>(200.0, 1000000), std::make_unique<SlowEstimator>(30),
             can::open_sink("candump:" + log));
  p.start();
  std::this_thread::sleep_for(std::chrono::milliseconds(500));
  p.request_stop();
  p.join();
  const auto msgs = read_candump_log(log);
  std::filesystem::remove(log);
  const HealthSnapshot h = snapshot(p.counters());
  EXPECT_GT(h.frames_captured, 50u);
  EXPECT_GT(h.ring_overruns, 10u) << "a full ring is counted, never silent";
  EXPECT_LT(h.frames_processed, h.frames_captured / 3);
  ASSERT_GE(msgs.status.size(), 3u);
  const auto& s = msgs.status[msgs.status.size() - 2].decoded.status_msg;
  EXPECT_NE(s.faults & can::kFaultRingOverrun, 0);
  EXPECT_GT(s.ring_overruns, 0u) << "the status message carries the overrun count";
  // The estimate that goes out is from a recent frame: the processing thread
  // takes the newest, so the age stays near one processing time.
  const PublishedEstimate latest = p.latest();
  EXPECT_GT(latest.sequence, 5u);
  EXPECT_LT(latest.published_ns - latest.captured_ns, 100 * drivers::kNsPerMs);
}

TEST(Pipeline, ExposureControlClosesTheLoopToTheCamera) {
  const std::string log = temp_log("exposure");
  DaemonConfig c = test_config();
  c.exposure_mode = "adaptive";
  auto camera = std::make_unique<ScriptedCamera>(100.0, 1000000);
  ScriptedCamera* cam = camera.get();
  Pipeline p(c, std::move(camera), make_frame_estimator("truth", {}), can::open_sink("candump:" + log));
  p.start();
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  p.request_stop();
  p.join();
  std::filesystem::remove(log);
  // 10 m/s at 0.1 mm/px: a streak of target_streak_px needs
  // target_streak_px * 1e-4 m / 10 m/s (e.g. 40 px -> 400 us).
  const double expected_us = dsp::ExposureLimits{}.target_streak_px * 1e-4 / 10.0 * 1e6;
  EXPECT_GE(cam->exposure_calls.load(), 1);
  EXPECT_NEAR(cam->last_exposure_us.load(), expected_us, 0.1 * expected_us);
  EXPECT_NE(cam->last_exposure_us.load(), c.exposure_initial_us) << "the plan must have changed";
  EXPECT_GE(p.counters().exposure_updates.load(), 1u);
}

TEST(Pipeline, BoundedRunSendsExactlyItsPeriods) {
  const std::string log = temp_log("bounded");
  DaemonConfig c = test_config();
  PipelineHooks hooks;
  hooks.max_ticks = 25;
  Pipeline p(c, std::make_unique<ScriptedCamera>(100.0, 1000000), make_frame_estimator("truth", {}),
             can::open_sink("candump:" + log), hooks);
  p.start();
  const std::int64_t t0 = drivers::mono_now_ns();
  while (!p.run_complete() && drivers::mono_now_ns() - t0 < 5 * drivers::kNsPerS) {
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  EXPECT_TRUE(p.run_complete());
  p.request_stop();
  p.join();
  const auto msgs = read_candump_log(log);
  std::filesystem::remove(log);
  EXPECT_EQ(msgs.velocity.size(), 25u);
  EXPECT_EQ(msgs.velocity_xy.size(), 25u);
  EXPECT_EQ(msgs.status.size(), 5u);
  EXPECT_EQ(msgs.timing.size(), 5u);
  EXPECT_EQ(msgs.ride_height.size(), 25u);
  EXPECT_EQ(msgs.unparsed, 0u);
  // No height source: every speed rests on the nominal height, and the bus says so.
  for (const auto& m : msgs.ride_height) {
    EXPECT_FALSE(m.decoded.ride.height_valid);
    EXPECT_EQ(m.decoded.ride.scale_source, can::ScaleSourceCode::Nominal);
  }
  for (std::size_t i = 1; i < msgs.status.size(); ++i) {  // the first may precede the first estimate
    EXPECT_NE(msgs.status[i].decoded.status_msg.faults & can::kFaultScaleUncorrected, 0) << "status " << i;
  }
  // Alive counters step by one per message of each ID.
  for (std::size_t i = 1; i < msgs.velocity.size(); ++i) {
    EXPECT_EQ(can::e2e_counter_delta(msgs.velocity[i - 1].decoded.counter, msgs.velocity[i].decoded.counter), 1);
  }
}

TEST(Pipeline, StopsWithin100Milliseconds) {
  const std::string log = temp_log("stop");
  DaemonConfig c = test_config();
  Pipeline p(c, std::make_unique<ScriptedCamera>(60.0, 1000000), make_frame_estimator("truth", {}),
             can::open_sink("candump:" + log));
  p.start();
  std::this_thread::sleep_for(std::chrono::milliseconds(150));
  const std::int64_t t0 = drivers::mono_now_ns();
  p.request_stop();
  p.join();
  const std::int64_t took = drivers::mono_now_ns() - t0;
  std::filesystem::remove(log);
  EXPECT_LT(took, 100 * drivers::kNsPerMs);
}

}  // namespace
}  // namespace gvs::daemon
