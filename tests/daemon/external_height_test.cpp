// [height] source = "can": an external distance sensor's height rescales
// each estimate at its instant, and the bus says which height the speed
// rests on. Threaded (the pipeline test): run under TSan and ASan too.
#include <gtest/gtest.h>
#include <unistd.h>

#include <atomic>
#include <cmath>
#include <chrono>
#include <filesystem>
#include <thread>

#include "gvs/can/sink.hpp"
#include "gvs/daemon/config.hpp"
#include "gvs/daemon/external_height.hpp"
#include "gvs/daemon/health.hpp"
#include "gvs/daemon/pipeline.hpp"
#include "gvs/drivers/clock.hpp"
#include "gvsd_test_support.hpp"
#include "scripted_camera.hpp"

namespace gvs::daemon {
namespace {

core::VelocityEstimate moving_estimate() {
  core::VelocityEstimate e;
  e.has_speed = e.has_direction = e.has_yaw_rate = true;
  e.vx_mps = 9.0;
  e.vy_mps = 1.0;
  e.speed_mps = std::hypot(9.0, 1.0);
  e.direction_deg = std::atan2(1.0, 9.0) * 180.0 / M_PI;
  e.yaw_rate_dps = 20.0;
  return e;
}

TEST(ExternalHeight, ScalesTheVelocityByHeightOverNominal) {
  core::VelocityEstimate e = moving_estimate();
  const core::VelocityEstimate before = e;
  EXPECT_TRUE(apply_external_height(e, 63.0, 60.0));  // 3 mm higher: 5 % more ground per pixel
  EXPECT_NEAR(e.vx_mps, before.vx_mps * 1.05, 1e-12);
  EXPECT_NEAR(e.vy_mps, before.vy_mps * 1.05, 1e-12);
  EXPECT_NEAR(e.speed_mps, before.speed_mps * 1.05, 1e-12);
  EXPECT_EQ(e.direction_deg, before.direction_deg);
  EXPECT_EQ(e.yaw_rate_dps, before.yaw_rate_dps);
  EXPECT_TRUE(e.ride.has_height);
  EXPECT_EQ(e.ride.height_mm, 63.0);
  EXPECT_FALSE(e.ride.has_pitch || e.ride.has_roll);
  EXPECT_EQ(e.scale_source, core::ScaleSource::external);
}

TEST(ExternalHeight, AHeightFarFromTheNominalIsNotTheCamerasAndScalesNothing) {
  for (const double h : {40.0, 44.0, 76.0, 600.0, 0.0, -5.0, std::nan("")}) {
    core::VelocityEstimate e = moving_estimate();
    const double speed = e.speed_mps;
    EXPECT_FALSE(apply_external_height(e, h, 60.0)) << h << " mm";
    EXPECT_EQ(e.speed_mps, speed) << h << " mm";
    EXPECT_FALSE(e.ride.has_height) << h << " mm";
    EXPECT_EQ(e.scale_source, core::ScaleSource::nominal) << h << " mm";
  }
  core::VelocityEstimate e = moving_estimate();
  EXPECT_TRUE(apply_external_height(e, 74.0, 60.0)) << "14 mm above: within the kerb strike's reach";
}

TEST(ExternalHeight, AHeightMeasuredInTheFrameWins) {
  core::VelocityEstimate e = moving_estimate();
  e.scale_source = core::ScaleSource::laser_dots;
  e.ride.has_height = true;
  e.ride.height_mm = 59.5;
  const double speed = e.speed_mps;
  EXPECT_FALSE(apply_external_height(e, 63.0, 60.0));
  EXPECT_EQ(e.speed_mps, speed);
  EXPECT_EQ(e.ride.height_mm, 59.5);
  EXPECT_EQ(e.scale_source, core::ScaleSource::laser_dots);
}

TEST(ExternalHeight, SignalFromTheKeysAsTheirDbcLine) {
  HeightConfig c;
  c.can_id = 0x6A1;
  c.start_bit = 7;
  c.length = 16;
  c.byte_order = "motorola";
  c.scale = 0.01;
  c.offset_mm = -5.0;
  const can::ForeignSignal s = external_height_signal(c);
  can::CanFrame f;
  f.id = 0x6A1;
  f.len = 8;
  f.data = {0x17, 0x70, 0, 0, 0, 0, 0, 0};  // raw 6000
  const auto v = can::read_signal(f, s);
  ASSERT_TRUE(v);
  EXPECT_NEAR(*v, 55.0, 1e-9);
}

DaemonConfig test_config() {
  DaemonConfig c;
  c.capture_thread.priority = 0;
  c.processing_thread.priority = 0;
  c.sender_thread.priority = 0;
  c.prefault_stack_kb = 64;
  c.height.source = "can";
  c.height.nominal_mm = 60.0;
  c.height.max_gap_ms = 20.0;
  return c;
}

std::string temp_log(const char* name) {
  return (std::filesystem::temp_directory_path() /
          ("gvsd_height_" + std::string(name) + "_" + std::to_string(getpid()) + ".log"))
      .string();
}

// A distance sensor at 1 kHz reading 66 mm (nominal 60: the truth's 10 m/s
// becomes 11 m/s), which falls silent after `silent_after` samples.
struct ScriptedSensor {
  std::int64_t next_ns = -1;
  int sent = 0;
  int silent_after = 1'000'000;
  void operator()(can::HeightHistory& h) {
    const std::int64_t now = drivers::mono_now_ns();
    if (next_ns < 0) next_ns = now - 50 * drivers::kNsPerMs;
    for (; next_ns <= now && sent < silent_after; next_ns += drivers::kNsPerMs, ++sent) h.add(next_ns, 66.0);
  }
};

struct PipelineRun {
  testing::CandumpLog msgs;
  HealthSnapshot health;  ///< at the end (the health line's height part)
};

PipelineRun run(const char* name, int silent_after, int ticks) {
  const std::string log = temp_log(name);
  PipelineHooks hooks;
  hooks.max_ticks = static_cast<std::uint64_t>(ticks);
  ScriptedSensor sensor;
  sensor.silent_after = silent_after;
  hooks.height_samples = [sensor](can::HeightHistory& h) mutable { sensor(h); };
  Pipeline p(test_config(), std::make_unique<testing::ScriptedCamera>(100.0, 1000000),
             make_frame_estimator("truth", {}), can::open_sink("candump:" + log), hooks);
  p.start();
  const std::int64_t t0 = drivers::mono_now_ns();
  while (!p.run_complete() && drivers::mono_now_ns() - t0 < 10 * drivers::kNsPerS) {
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  p.request_stop();
  p.join();
  PipelineRun r{testing::read_candump_log(log), snapshot(p.counters())};
  std::filesystem::remove(log);
  return r;
}

TEST(ExternalHeightPipeline, SpeedScaledByTheSensorsHeightAndTheBusSaysExternal) {
  const PipelineRun pr = run("on", 1'000'000, 30);
  const testing::CandumpLog& msgs = pr.msgs;
  ASSERT_EQ(msgs.ride_height.size(), 30u);
  int valid = 0;
  for (std::size_t i = 0; i < msgs.velocity.size(); ++i) {
    const can::VelocityMsg& v = msgs.velocity[i].decoded.velocity;
    const can::RideHeightMsg& r = msgs.ride_height[i].decoded.ride;
    if (!v.speed_valid) continue;
    ++valid;
    EXPECT_NEAR(v.speed_mps, 11.0, 0.01) << "message " << i << ": 10 m/s at 66 mm over a nominal 60";
    EXPECT_EQ(msgs.velocity_xy[i].decoded.xy.scale_source, can::ScaleSourceCode::External);
    EXPECT_TRUE(r.height_valid);
    EXPECT_NEAR(r.height_mm, 66.0, 0.005 + 1e-9);
    EXPECT_FALSE(r.pitch_valid || r.roll_valid);
    EXPECT_EQ(r.scale_source, can::ScaleSourceCode::External);
  }
  // How many go out valid (fresh) depends on the machine's spare CPU; every
  // one that does must carry the right scale.
  EXPECT_GT(valid, 0);
  for (std::size_t i = 1; i < msgs.status.size(); ++i) {
    EXPECT_EQ(msgs.status[i].decoded.status_msg.faults & can::kFaultScaleUncorrected, 0) << "status " << i;
  }
  // The health line's height part: the sensor's readings (1 kHz, 50 before
  // the start) and each estimate once, scaled or left nominal (one that
  // waited longer than the history's 64 ms on a busy machine).
  EXPECT_GE(pr.health.height_samples, 50u + 300u);
  EXPECT_GT(pr.health.height_scaled, 0u);
  EXPECT_EQ(pr.health.height_scaled + pr.health.height_unscaled, pr.health.frames_processed);
}

TEST(ExternalHeightPipeline, ASilentSensorLeavesTheScaleUncorrectedAndFlagged) {
  const PipelineRun pr = run("silent", 0, 30);
  const testing::CandumpLog& msgs = pr.msgs;
  int valid = 0;
  for (std::size_t i = 0; i < msgs.velocity.size(); ++i) {
    const can::VelocityMsg& v = msgs.velocity[i].decoded.velocity;
    if (!v.speed_valid) continue;
    ++valid;
    EXPECT_NEAR(v.speed_mps, 10.0, 0.01) << "message " << i << ": no height, the nominal scale";
    EXPECT_EQ(msgs.velocity_xy[i].decoded.xy.scale_source, can::ScaleSourceCode::Nominal);
    EXPECT_FALSE(msgs.ride_height[i].decoded.ride.height_valid);
  }
  // How many go out valid (fresh) depends on the machine's spare CPU; every
  // one that does must carry the right scale.
  EXPECT_GT(valid, 0);
  for (std::size_t i = 1; i < msgs.status.size(); ++i) {
    EXPECT_NE(msgs.status[i].decoded.status_msg.faults & can::kFaultScaleUncorrected, 0) << "status " << i;
  }
  EXPECT_EQ(pr.health.height_samples, 0u);
  EXPECT_EQ(pr.health.height_scaled, 0u);
  EXPECT_GT(pr.health.height_unscaled, 20u);
  EXPECT_EQ(pr.health.height_unscaled, pr.health.frames_processed);
  const std::string line = format_health_line(pr.health, HealthSnapshot{}, PublishedEstimate{}, 0, 1.0);
  EXPECT_NE(line.find(" | height 0 samples, read errors 0 (+0), scaled 0 (+0), nominal "), std::string::npos)
      << "a silent sensor shows in the health line: " << line;
}

TEST(ExternalHeightConfig, RefusedWithoutAnInterfaceOrWithASignalOutsideTheFrame) {
  const auto parse = [](const std::string& can, const std::string& height) {
    return parse_config("[can]\nuri = \"" + can + "\"\n[height]\nsource = \"can\"\n" + height, "test.toml");
  };
  EXPECT_THROW(parse("candump:-", ""), ConfigError) << "no interface to receive on";
  EXPECT_EQ(parse("socketcan:can0", "").height.source, "can");
  EXPECT_EQ(parse("candump:-", "interface = \"can1\"\n").height.interface, "can1");
  EXPECT_THROW(parse("socketcan:can0", "start_bit = 60\n"), ConfigError) << "16 bits from bit 60 run past byte 7";
  EXPECT_THROW(parse("socketcan:can0", "can_id = 0x800\n"), ConfigError) << "not an 11-bit ID";
  EXPECT_NO_THROW(parse("socketcan:can0", "can_id = 0x800\nextended = true\n"));
  try {
    parse("socketcan:can0", "start_bit = 60\n");
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("test.toml"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("[height]"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace gvs::daemon
