// gvsd building blocks: the seqlock, the configuration, the lever arm. The
// two-thread tests here are the ones to run under TSan (the SPSC ring's:
// tests/drivers/spsc_ring_test.cpp).
#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <filesystem>
#include <stdexcept>
#include <thread>

#include <opencv2/core.hpp>
#include <opencv2/core/utils/logger.hpp>

#include "gvs/daemon/config.hpp"
#include "gvs/daemon/frame_estimator.hpp"
#include "gvs/daemon/health.hpp"
#include "gvs/daemon/logging.hpp"
#include "gvs/daemon/pipeline.hpp"
#include "gvs/daemon/seqlock.hpp"

namespace gvs::daemon {
namespace {

struct Sample {
  std::uint64_t a = 0;
  double b = 0.0;
  std::int64_t c = 0;
  std::array<std::uint32_t, 9> d{};
};

TEST(Seqlock, ReadsTheLastWriteAndCountsVersions) {
  Seqlock<Sample> lock;
  EXPECT_EQ(lock.version(), 0u);
  EXPECT_EQ(lock.read().a, 0u);
  Sample s;
  s.a = 5;
  s.b = 2.5;
  s.d[8] = 77;
  lock.write(s);
  EXPECT_EQ(lock.version(), 1u);
  const Sample r = lock.read();
  EXPECT_EQ(r.a, 5u);
  EXPECT_EQ(r.b, 2.5);
  EXPECT_EQ(r.d[8], 77u);
}

TEST(Seqlock, ReaderNeverSeesAHalfWrittenValue) {
  Seqlock<Sample> lock;
  std::atomic<bool> done{false};
  std::thread writer([&] {
    for (std::uint64_t i = 1; i <= 300000; ++i) {
      Sample s;
      s.a = i;
      s.b = static_cast<double>(i);
      s.c = -static_cast<std::int64_t>(i);
      s.d.fill(static_cast<std::uint32_t>(i));
      lock.write(s);
    }
    done.store(true);
  });
  std::uint64_t reads = 0, torn = 0, last = 0, backwards = 0;
  while (!done.load()) {
    const Sample s = lock.read();
    ++reads;
    bool ok = s.b == static_cast<double>(s.a) && s.c == -static_cast<std::int64_t>(s.a);
    for (std::uint32_t v : s.d) ok = ok && v == static_cast<std::uint32_t>(s.a);
    torn += ok ? 0 : 1;
    backwards += s.a < last ? 1 : 0;
    last = s.a;
  }
  writer.join();
  EXPECT_EQ(torn, 0u);
  EXPECT_EQ(backwards, 0u);
  EXPECT_GT(reads, 0u);
  EXPECT_EQ(lock.read().a, 300000u);
}

// ---- configuration ----

std::filesystem::path example_config() {
  return std::filesystem::path(GVSD_SOURCE_DIR) / "systemd" / "gvsd.toml";
}

TEST(Config, TheDocumentedExampleParsesToTheDefaults) {
  const DaemonConfig file = load_config_file(example_config());
  const DaemonConfig defaults;
  EXPECT_TRUE(restart_only_changes(file, defaults).empty());
  EXPECT_EQ(file.source_uri, "sim:sine");
  EXPECT_EQ(file.can_uri, "candump:-");
  EXPECT_EQ(file.staleness_limit_ms, defaults.staleness_limit_ms);
  EXPECT_EQ(file.min_quality, defaults.min_quality);
  EXPECT_EQ(file.min_quality, 0.3);
  EXPECT_TRUE(file.plausibility == defaults.plausibility) << "gvsd.toml's [plausibility] shows the defaults";
  EXPECT_EQ(file.plausibility.max_accel_mps2, 29.4);
  EXPECT_EQ(file.exposure_mode, defaults.exposure_mode);
  EXPECT_EQ(file.log_level, defaults.log_level);
  EXPECT_EQ(file.health_interval_s, defaults.health_interval_s);
  EXPECT_EQ(file.base_id, 0x300u);
  EXPECT_EQ(file.capture_thread.priority, 80);
}

TEST(Config, ReadsEverySection) {
  const DaemonConfig c = parse_config(R"(
[source]
uri = "replay:/data/run1"
ring_slots = 8
[can]
uri = "socketcan:vcan0"
staleness_limit_ms = 30
base_id = 0x400
[camera]
mm_per_px = 0.2
mount_yaw_deg = -2.5
lever_arm_x_m = 1.2
[estimator]
method = "thesis-fft"
[exposure]
mode = "double-pulse"
[threads]
sender = { priority = 95, cpu = 1 }
lock_memory = false
[log]
level = "debug"
)",
                                      "test.toml");
  EXPECT_EQ(c.source_uri, "replay:/data/run1");
  EXPECT_EQ(c.ring_slots, 8);
  EXPECT_EQ(c.can_uri, "socketcan:vcan0");
  EXPECT_EQ(c.staleness_limit_ms, 30.0);
  EXPECT_EQ(c.base_id, 0x400u);
  EXPECT_EQ(c.camera.mm_per_px, 0.2);
  EXPECT_EQ(c.camera.mount_yaw_deg, -2.5);
  EXPECT_EQ(c.lever_arm_x_m, 1.2);
  EXPECT_EQ(c.estimator_method, "thesis-fft");
  EXPECT_EQ(c.exposure_mode, "double-pulse");
  EXPECT_EQ(c.sender_thread.priority, 95);
  EXPECT_EQ(c.sender_thread.cpu, 1);
  EXPECT_FALSE(c.lock_memory);
  EXPECT_EQ(c.log_level, "debug");
}

std::string error_of(const std::string& text) {
  try {
    (void)parse_config(text, "bad.toml");
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "(no error)";
}

TEST(Config, UnknownKeyIsNamedWithTheKnownOnes) {
  const std::string e = error_of("[can]\nstalenes_limit_ms = 20\n");
  EXPECT_NE(e.find("bad.toml:2"), std::string::npos) << e;
  EXPECT_NE(e.find("unknown key 'stalenes_limit_ms' in [can]"), std::string::npos) << e;
  EXPECT_NE(e.find("staleness_limit_ms"), std::string::npos) << e;
  EXPECT_NE(error_of("[cann]\nuri = \"x\"\n").find("unknown key 'cann'"), std::string::npos);
  EXPECT_NE(error_of("[threads.capture]\nprio = 3\n").find("[threads.capture]"), std::string::npos);
}

TEST(Config, WrongTypeNamesKeyAndRange) {
  const std::string e = error_of("[can]\nstaleness_limit_ms = \"fifty\"\n");
  EXPECT_NE(e.find("[can] staleness_limit_ms must be a number"), std::string::npos) << e;
  EXPECT_NE(e.find("1 .. 1000 ms"), std::string::npos) << e;
  EXPECT_NE(error_of("[source]\nring_slots = 4.5\n").find("ring_slots must be an integer"), std::string::npos);
  EXPECT_NE(error_of("[threads]\nlock_memory = 1\n").find("lock_memory must be true or false"), std::string::npos);
}

TEST(Config, OutOfRangeNamesKeyAndRange) {
  const std::string e = error_of("[threads.sender]\npriority = 120\n");
  EXPECT_NE(e.find("[threads.sender] priority = 120 is out of range"), std::string::npos) << e;
  EXPECT_NE(e.find("0 .. 99"), std::string::npos) << e;
  EXPECT_NE(error_of("[log]\nlevel = \"loud\"\n").find("one of: trace"), std::string::npos);
  EXPECT_NE(error_of("[can]\nperiod_ms = 20\nstatus_period_ms = 50\n").find("multiple of period_ms"),
            std::string::npos);
  EXPECT_NE(error_of("[exposure]\ninitial_us = 5000\nmax_us = 3000\n").find("initial_us <= max_us"),
            std::string::npos);
  EXPECT_NE(error_of("[camera]\nmm_per_px = 0\n").find("mm_per_px = 0 is out of range"), std::string::npos);
  EXPECT_NE(error_of("not toml [").find("not valid TOML"), std::string::npos);
}

// toml++ 3.3.0 has undefined behaviour on some non-ASCII characters where it
// expects whitespace (found by fuzz_config); TOML allows them only in strings
// and comments, so gvsd refuses them elsewhere before toml++ reads them.
TEST(Config, NonAsciiOnlyInStringsAndComments) {
  const std::string mu = "\xC2\xB5";  // U+00B5, one of the characters that reached toml++'s UB
  EXPECT_EQ(parse_config("# exposure in " + mu + "s\n[log]\nlevel = \"info\" # " + mu + "\n", "t.toml").log_level,
            "info");
  EXPECT_EQ(parse_config("\xEF\xBB\xBF[can]\nperiod_ms = 10\n", "t.toml").period_ms, 10);  // byte-order mark
  EXPECT_EQ(parse_config("[source]\nuri = \"file:/m" + mu + "/\\\"x\\\"\" # " + mu + "\n", "t.toml").source_uri,
            "file:/m" + mu + "/\"x\"");
  EXPECT_EQ(parse_config("[source]\nuri = '''sim:" + mu + "'''\n", "t.toml").source_uri, "sim:" + mu);
  // Outside strings and comments: the line, and what is allowed where.
  for (const std::string& bad :
       {"[can]\nperiod_ms = 2" + mu + "\n", "[can]\n" + mu + " = 1\n", "[log]\nlevel = \"info\"\n[" + mu + "]\n",
        "[log] # \" \nlevel = \"info\" " + mu + "\n", "[can]\nperiod_ms = +0'''+'" + mu + "\n"}) {
    const std::string e = error_of(bad);
    EXPECT_NE(e.find("not valid TOML"), std::string::npos) << e;
    EXPECT_NE(e.find("is allowed only in a quoted string or a comment"), std::string::npos) << e;
  }
  EXPECT_NE(error_of("[log]\nlevel = \"info\"\n[" + mu + "]\n").find("bad.toml:3:"), std::string::npos);
  // A multi-line basic string, where toml++ trims whitespace after a backslash.
  const std::string e = error_of("[source]\nuri = \"\"\"x \\\n " + mu + "\"\"\"\n");
  EXPECT_NE(e.find("bad.toml:3: a non-ASCII character in a multi-line"), std::string::npos) << e;
}

// Issue #22: the CAN period is configurable from 4 to 100 ms (default 20, as
// the ECU expects); the simulated camera takes up to 250 fps and beyond.
TEST(Config, CanPeriodIsFourToOneHundredMilliseconds) {
  EXPECT_EQ(DaemonConfig{}.period_ms, 20);
  EXPECT_EQ(parse_config("[can]\nperiod_ms = 4\n", "t.toml").period_ms, 4);
  EXPECT_EQ(parse_config("[can]\nperiod_ms = 100\n", "t.toml").period_ms, 100);
  for (const char* bad : {"3", "101", "0"}) {
    const std::string e = error_of(std::string("[can]\nperiod_ms = ") + bad + "\n");
    EXPECT_NE(e.find("[can] period_ms = " + std::string(bad) + " is out of range"), std::string::npos) << e;
    EXPECT_NE(e.find("4 .. 100 ms"), std::string::npos) << e;
  }
  EXPECT_EQ(parse_config("[source]\nsim_fps = 250\n", "t.toml").sim_fps, 250.0);
}

// gvsd is built without the thesis's ORB methods (gvs::dsp_orb): its
// configuration offers the others and refuses those.
TEST(Config, EstimatorMethodsAreTheDaemonsOwn) {
  EXPECT_EQ(parse_config("[estimator]\nmethod = \"thesis-laplacian\"\n", "t.toml").estimator_method,
            "thesis-laplacian");
  const std::string e = error_of("[estimator]\nmethod = \"thesis-orb\"\n");
  EXPECT_NE(e.find("one of: gvs, thesis-fft, thesis-laplacian, truth"), std::string::npos) << e;
}

TEST(Config, PrefaultedStackIsAtMostHalfTheStack) {
  const DaemonConfig c = parse_config("[threads]\nstack_kb = 512\nprefault_stack_kb = 256\n", "t.toml");
  EXPECT_EQ(c.stack_kb, 512);
  const std::string e = error_of("[threads]\nstack_kb = 256\n");  // default prefault: 256 KiB
  EXPECT_NE(e.find("prefault_stack_kb (256) must be at most half of stack_kb (256)"), std::string::npos) << e;
  EXPECT_NE(error_of("[threads]\nstack_kb = 64\n").find("stack_kb = 64 is out of range"), std::string::npos);
}

TEST(Config, MinQualityAndPlausibilityKeysAreRead) {
  const DaemonConfig c = parse_config(R"(
[can]
min_quality = 0.35
[plausibility]
max_accel_mps2 = 20
speed_noise_mps = 0.5
speed_noise_fraction = 0.1
max_yaw_rate_dps = 250
direction_noise_deg = 5
min_direction_speed_mps = 2
reacquire_count = 8
track_timeout_ms = 300
)",
                                      "test.toml");
  EXPECT_EQ(c.min_quality, 0.35);
  EXPECT_EQ(c.plausibility.max_accel_mps2, 20.0);
  EXPECT_EQ(c.plausibility.speed_noise_mps, 0.5);
  EXPECT_EQ(c.plausibility.speed_noise_fraction, 0.1);
  EXPECT_EQ(c.plausibility.max_yaw_rate_dps, 250.0);
  EXPECT_EQ(c.plausibility.direction_noise_deg, 5.0);
  EXPECT_EQ(c.plausibility.min_direction_speed_mps, 2.0);
  EXPECT_EQ(c.plausibility.reacquire_count, 8);
  EXPECT_EQ(c.plausibility.track_timeout_ms, 300.0);
  EXPECT_EQ(parse_config("[can]\nmin_quality = 0\n", "t").min_quality, 0.0) << "0 and 1 are allowed";
  EXPECT_EQ(parse_config("[can]\nmin_quality = 1\n", "t").min_quality, 1.0);
  // Both are reloadable: changing them needs no restart.
  EXPECT_TRUE(restart_only_changes(DaemonConfig{}, c).empty());
}

TEST(Config, MinQualityAndPlausibilityOutOfRangeNameTheKey) {
  std::string e = error_of("[can]\nmin_quality = 1.5\n");
  EXPECT_NE(e.find("bad.toml:2: [can] min_quality = 1.5 is out of range (allowed 0 .. 1"), std::string::npos) << e;
  e = error_of("[can]\nmin_quality = -0.1\n");
  EXPECT_NE(e.find("[can] min_quality = -0.1 is out of range"), std::string::npos) << e;
  e = error_of("[can]\nmin_quality = \"high\"\n");
  EXPECT_NE(e.find("[can] min_quality must be a number"), std::string::npos) << e;
  e = error_of("[plausibility]\nmax_accel_mps2 = 0.5\n");
  EXPECT_NE(e.find("[plausibility] max_accel_mps2 = 0.5 is out of range (allowed 1 .. 200 m/s^2)"), std::string::npos)
      << e;
  e = error_of("[plausibility]\nreacquire_count = 1\n");
  EXPECT_NE(e.find("[plausibility] reacquire_count = 1 is out of range"), std::string::npos) << e;
  e = error_of("[plausibility]\nmax_acel_mps2 = 20\n");
  EXPECT_NE(e.find("unknown key 'max_acel_mps2' in [plausibility]"), std::string::npos) << e;
}

TEST(Config, SimGroundIsReadAndCheckedAtStartUp) {
  EXPECT_EQ(DaemonConfig{}.sim_ground, "procedural");
  EXPECT_EQ(parse_config("[source]\nsim_ground = \"photo:/data/asphalt.png:0.15\"\n", "t.toml").sim_ground,
            "photo:/data/asphalt.png:0.15");
  const std::string unknown = error_of("[source]\nsim_ground = \"gravel\"\n");
  EXPECT_NE(unknown.find("bad.toml: [source] sim_ground"), std::string::npos) << unknown;
  EXPECT_NE(unknown.find("photo:FILE[:MM_PER_PIXEL]"), std::string::npos) << unknown;
  const std::string scale = error_of("[source]\nsim_ground = \"photo:asphalt.png:big\"\n");
  EXPECT_NE(scale.find("asphalt.png"), std::string::npos) << scale;
  DaemonConfig a;
  DaemonConfig b;
  b.sim_ground = "photo:asphalt.png";
  const auto changed = restart_only_changes(a, b);
  ASSERT_EQ(changed.size(), 1u);
  EXPECT_EQ(changed[0], "source.sim_ground");
}

TEST(Config, MissingFileSaysSo) {
  EXPECT_THROW((void)load_config_file("/nonexistent/gvsd.toml"), ConfigError);
}

TEST(Config, RestartOnlyChangesAreListedByKey) {
  DaemonConfig a;
  DaemonConfig b;
  b.staleness_limit_ms = 20;  // reloadable
  b.log_level = "debug";      // reloadable
  EXPECT_TRUE(restart_only_changes(a, b).empty());
  b.source_uri = "sim:const";
  b.sender_thread.priority = 10;
  const auto changed = restart_only_changes(a, b);
  ASSERT_EQ(changed.size(), 2u);
  EXPECT_EQ(changed[0], "source.uri");
  EXPECT_EQ(changed[1], "threads.sender.priority");
}

// ---- lever arm ----

TEST(LeverArm, YawRateMovesTheVelocityToTheReferencePoint) {
  // Car turning left at 30 deg/s, sensor 1.5 m ahead of the reference point
  // and 0.2 m to the left: v_sensor = v_ref + omega x r.
  core::VelocityEstimate e;
  e.has_speed = e.has_direction = e.has_yaw_rate = true;
  const double omega = 30.0 * M_PI / 180.0;
  const double vx_ref = 10.0, vy_ref = 0.0, rx = 1.5, ry = 0.2;
  e.vx_mps = vx_ref - omega * ry;
  e.vy_mps = vy_ref + omega * rx;
  e.yaw_rate_dps = 30.0;
  e.speed_mps = std::hypot(e.vx_mps, e.vy_mps);
  apply_lever_arm(e, rx, ry);
  EXPECT_NEAR(e.vx_mps, vx_ref, 1e-12);
  EXPECT_NEAR(e.vy_mps, vy_ref, 1e-12);
  EXPECT_NEAR(e.speed_mps, 10.0, 1e-12);
  EXPECT_NEAR(e.direction_deg, 0.0, 1e-9);
}

TEST(LeverArm, WithoutYawRateTheEstimateStaysAtTheSensor) {
  core::VelocityEstimate e;
  e.has_speed = e.has_direction = true;
  e.vx_mps = 5.0;
  e.vy_mps = 1.0;
  apply_lever_arm(e, 1.0, 1.0);
  EXPECT_EQ(e.vx_mps, 5.0);
  EXPECT_EQ(e.vy_mps, 1.0);
}

TEST(Watchdog, FedOnlyWhileEveryThreadProgresses) {
  Progress p;
  WatchdogGate gate(p);
  EXPECT_FALSE(gate.should_feed(p)) << "nothing moved";
  for (auto& b : p.beats) ++b;
  EXPECT_TRUE(gate.should_feed(p));
  for (std::size_t hung = 0; hung < kThreadCount; ++hung) {
    // One thread hangs: the others keep beating, the watchdog starves.
    for (int k = 0; k < 5; ++k) {
      for (std::size_t i = 0; i < kThreadCount; ++i) p.beats[i] += i == hung ? 0 : 3;
      EXPECT_FALSE(gate.should_feed(p)) << role_name(static_cast<ThreadRole>(hung)) << " hung";
    }
    // It comes back: fed again.
    p.beats[hung] += 1;
    EXPECT_TRUE(gate.should_feed(p)) << role_name(static_cast<ThreadRole>(hung)) << " recovered";
  }
}

TEST(Logging, AnOpenCvExceptionReadsAsOneLineAndOpenCvsOwnLogIsOff) {
  try {
    cv::Mat a(4, 4, CV_8UC1, cv::Scalar(1)), b(3, 3, CV_8UC1, cv::Scalar(1)), sum;
    cv::add(a, b, sum);  // sizes differ
    FAIL() << "cv::add did not throw";
  } catch (const cv::Exception& e) {
    const std::string raw = e.what();
    const std::string line = describe_exception(e);
    EXPECT_NE(raw.find(".cpp"), std::string::npos) << "OpenCV's text names its source file: " << raw;
    EXPECT_EQ(line.rfind("OpenCV: ", 0), 0u) << line;
    EXPECT_EQ(line.find(".cpp"), std::string::npos) << line;
    EXPECT_EQ(line.find('\n'), std::string::npos) << line;
    EXPECT_NE(line.find("(in "), std::string::npos) << "the function that failed: " << line;
  }
  EXPECT_EQ(describe_exception(std::runtime_error("plain")), "plain");
  cv::utils::logging::setLogLevel(cv::utils::logging::LOG_LEVEL_WARNING);
  silence_library_logs();
  EXPECT_EQ(cv::utils::logging::getLogLevel(), cv::utils::logging::LOG_LEVEL_SILENT);
}

TEST(Health, LineCarriesTheCounters) {
  HealthSnapshot prev;
  HealthSnapshot now;
  now.frames_captured = 300;
  now.ring_overruns = 2;
  now.late_wakeups = 4;
  now.send_errors = 1;
  now.estimator_failures = 7;
  now.direction_only = 11;
  now.frames_rejected = 5;
  now.frames_dropped = 3;
  now.implausible_estimates = 2;
  PublishedEstimate latest;
  const std::string line = format_health_line(now, prev, latest, 0, 5.0);
  EXPECT_NE(line.find("capture 300 frames (60.0 fps)"), std::string::npos) << line;
  EXPECT_NE(line.find("ring overruns 2 (+2)"), std::string::npos) << line;
  EXPECT_NE(line.find("source dropped 3"), std::string::npos) << line;
  EXPECT_NE(line.find("late wake-ups 4"), std::string::npos) << line;
  EXPECT_NE(line.find("send errors 1"), std::string::npos) << line;
  EXPECT_NE(line.find("no estimate 7"), std::string::npos) << line;
  EXPECT_NE(line.find("direction only 11"), std::string::npos) << line;
  EXPECT_NE(line.find("rejected 5 (+5),"), std::string::npos) << "no reason counted, none listed: " << line;
  EXPECT_NE(line.find("implausible 2 (+2)"), std::string::npos) << line;
  EXPECT_NE(line.find("no estimate yet"), std::string::npos) << line;
  latest.sequence = 9;
  latest.estimate.has_speed = latest.estimate.has_direction = true;
  latest.estimate.speed_mps = 0.0;
  latest.plausible = false;
  const std::string held = format_health_line(now, prev, latest, 0, 5.0);
  EXPECT_NE(held.find("implausible (held back)"), std::string::npos) << held;
}

TEST(Health, LineSaysWhichSideLostFrames) {
  // The camera's drops ("source dropped", capture part), gvsd's capture
  // losses ("ring overruns", capture part) and the estimator passing over
  // older frames ("skipped", processing part) are three separate counts,
  // each in its own part of the line.
  HealthSnapshot prev;
  HealthSnapshot now;
  now.frames_dropped = 3;
  now.ring_overruns = 5;
  now.frames_skipped = 7;
  const std::string line = format_health_line(now, prev, PublishedEstimate{}, 0, 5.0);
  const auto processing = line.find("| processing ");
  ASSERT_NE(processing, std::string::npos) << line;
  const auto dropped = line.find("source dropped 3 (+3)");
  const auto overruns = line.find("ring overruns 5 (+5)");
  const auto skipped = line.find("skipped 7 (+7)");
  ASSERT_NE(dropped, std::string::npos) << line;
  ASSERT_NE(overruns, std::string::npos) << line;
  ASSERT_NE(skipped, std::string::npos) << line;
  EXPECT_LT(dropped, processing) << "the source's drops belong to the capture part: " << line;
  EXPECT_LT(overruns, processing) << line;
  EXPECT_GT(skipped, processing) << "the estimator's skips belong to the processing part: " << line;
  // Nothing lost: every count reads 0.
  const std::string quiet = format_health_line(prev, prev, PublishedEstimate{}, 0, 5.0);
  EXPECT_NE(quiet.find("source dropped 0 (+0)"), std::string::npos) << quiet;
  EXPECT_NE(quiet.find("skipped 0 (+0)"), std::string::npos) << quiet;
}

TEST(Health, LineNamesEachRejectReason) {
  HealthSnapshot prev;
  HealthSnapshot now;
  prev.frames_rejected_by[static_cast<std::size_t>(core::RejectReason::unreadable)] = 1;
  now.frames_rejected_by[static_cast<std::size_t>(core::RejectReason::unreadable)] = 2;
  now.frames_rejected_by[static_cast<std::size_t>(core::RejectReason::no_light_in_exposure)] = 4;
  prev.frames_rejected = 1;
  now.frames_rejected = 6;
  const std::string line = format_health_line(now, prev, PublishedEstimate{}, 0, 5.0);
  EXPECT_NE(line.find("rejected 6 (+5) [unreadable 2 (+1), no-light-in-exposure 4 (+4)]"), std::string::npos)
      << line;
  EXPECT_EQ(line.find("wrong-size"), std::string::npos) << "reasons that never occurred are left out: " << line;
}

}  // namespace
}  // namespace gvs::daemon
