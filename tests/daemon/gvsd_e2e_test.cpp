// gvsd as a process: the 10 s acceptance run on sim:sine, signals, sd_notify and the
// watchdog, configuration errors, journal-friendly logging, the no-argument
// desk run. Runs the real binary (GVSD_BINARY).
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <regex>
#include <sstream>
#include <thread>

#include "gvs/drivers/clock.hpp"
#include "gvs/drivers/dataset.hpp"
#include "gvs/drivers/simulator.hpp"
#include "gvs/core/laser_geometry.hpp"
#include "gvs/core/method.hpp"
#include "gvsd_test_support.hpp"

namespace gvs::daemon {
namespace {

using testing::quantile;
using testing::read_candump_log;

namespace fs = std::filesystem;

fs::path temp_dir() {
  static const fs::path dir = [] {
    fs::path d = fs::temp_directory_path() / ("gvsd_e2e_" + std::to_string(getpid()));
    fs::create_directories(d);
    return d;
  }();
  return dir;
}

std::string slurp(const fs::path& p) {
  std::ifstream in(p);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

struct Child {
  pid_t pid = -1;
  fs::path out, err;
};

/// Starts gvsd with `args`; stdout and stderr go to files. `env` entries are
/// set ("K=V") or removed ("K=") in the child; INVOCATION_ID and
/// JOURNAL_STREAM are removed unless given.
Child spawn(const std::vector<std::string>& args, const std::string& name,
            const std::map<std::string, std::string>& env = {}) {
  Child c;
  c.out = temp_dir() / (name + ".out");
  c.err = temp_dir() / (name + ".err");
  c.pid = fork();
  if (c.pid == 0) {
    unsetenv("INVOCATION_ID");
    unsetenv("JOURNAL_STREAM");
    unsetenv("NOTIFY_SOCKET");
    unsetenv("WATCHDOG_USEC");
    for (const auto& [k, v] : env) setenv(k.c_str(), v.c_str(), 1);
    freopen(c.out.c_str(), "w", stdout);
    freopen(c.err.c_str(), "w", stderr);
    std::vector<char*> argv;
    std::string bin = GVSD_BINARY;
    argv.push_back(bin.data());
    std::vector<std::string> copy = args;
    for (std::string& a : copy) argv.push_back(a.data());
    argv.push_back(nullptr);
    execv(bin.c_str(), argv.data());
    _exit(127);
  }
  return c;
}

int wait_exit(const Child& c) {
  int status = 0;
  waitpid(c.pid, &status, 0);
  return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}

fs::path write_config(const std::string& name, const std::string& text) {
  const fs::path p = temp_dir() / name;
  std::ofstream(p) << text;
  return p;
}

constexpr double kSineSpeedMps = 60.0 / 3.6;

/// How the source paces its frames, which decides what the valid fraction says.
enum class Pace {
  Camera,     ///< frames at their own 60 fps (replay): >= 95 % of periods valid
  CpuBound,   ///< the live simulator renders as fast as spare CPU allows: the
              ///< valid fraction follows from that and is not asserted; the
              ///< validity rule and the valid values are
};

/// The acceptance run: 10 s of `source` (sim:sine) to a candump file.
void must_show_run(const std::string& method, const std::string& source, Pace pace) {
  const fs::path log = temp_dir() / ("must_show_" + method + ".log");
  std::vector<std::string> args{"--source", source, "--can", "candump:" + log.string(), "--run-for", "10"};
  if (method != "gvs") {
    args.push_back("--config");
    args.push_back(write_config("method_" + method + ".toml", "[estimator]\nmethod = \"" + method + "\"\n").string());
  }
  const Child c = spawn(args, "must_show_" + method);
  ASSERT_EQ(wait_exit(c), 0) << slurp(c.err);
  const auto msgs = read_candump_log(log.string());
  EXPECT_EQ(msgs.unparsed, 0u);
  EXPECT_EQ(msgs.bad_crc, 0u);
  EXPECT_EQ(msgs.velocity.size(), 500u);
  EXPECT_EQ(msgs.velocity_xy.size(), 500u);
  EXPECT_EQ(msgs.status.size(), 100u);
  ASSERT_GT(msgs.velocity.size(), 100u);

  // Timing of the 20 ms schedule.
  const std::vector<double> periods = testing::periods_ms(msgs.velocity);
  std::vector<double> deviation;
  for (double p : periods) deviation.push_back(std::fabs(p - 20.0));
  const double median = quantile(periods, 0.5);
  const double p99 = quantile(deviation, 0.99);
  EXPECT_NEAR(median, 20.0, 0.1);
  // Jitter (the target "p99 deviation under 2 ms") is what spare CPU buys:
  // gvsd_latency_bench measures it on a quiet machine for
  // docs/performance.md. Here, beside the rest of the suite, the schedule's
  // shape is checked: it keeps its phase (lateness never accumulates), and
  // a period skipped in a stall is one gvsd flagged as a deadline miss.
  const testing::ScheduleHold hold = testing::schedule_hold(msgs.velocity, 20.0);
  EXPECT_LT(std::fabs(hold.off_grid_ms), 2.0) << "the schedule drifted by " << hold.phase_step_ms << " ms";
  EXPECT_GE(hold.whole_periods, 0);
  if (hold.whole_periods > 0) {
    const bool flagged = std::any_of(msgs.status.begin(), msgs.status.end(), [](const testing::LoggedMessage& m) {
      return (m.decoded.status_msg.faults & can::kFaultDeadlineMiss) != 0;
    });
    EXPECT_TRUE(flagged) << hold.whole_periods << " period(s) skipped and no status message flagged a deadline miss";
  }
  const std::vector<double> status_periods = testing::periods_ms(msgs.status);
  EXPECT_NEAR(quantile(status_periods, 0.5), 100.0, 0.5);

  // GVS_Method names the newest estimate's method with its own code: never
  // 255, always one of the table's, and the run's measurements show up.
  std::map<std::string, int> method_counts;
  int measured = 0;
  for (const testing::LoggedMessage& m : msgs.status) {
    if (m.decoded.status_msg.state == can::SensorState::Init) continue;
    const std::uint8_t code = m.decoded.status_msg.method;
    EXPECT_NE(code, 255) << "GVS_Method 255 (unknown)";
    const std::optional<core::Method> sent = core::method_from_can_code(code);
    ASSERT_TRUE(sent.has_value()) << "GVS_Method " << int{code} << " is not in core::kMethods";
    ++method_counts[core::method_word(*sent)];
    const bool gvs_measurement = *sent == core::Method::pair || *sent == core::Method::still ||
                                 *sent == core::Method::blur_cont || *sent == core::Method::blur_energy ||
                                 *sent == core::Method::blur_fwd || *sent == core::Method::dpiv_cont ||
                                 *sent == core::Method::dpiv_energy || *sent == core::Method::dpiv_fwd;
    if (method == "truth" ? *sent == core::Method::truth : gvs_measurement) ++measured;
  }
  std::string seen;
  for (const auto& [word, n] : method_counts) seen += " " + word + "=" + std::to_string(n);
  std::printf("[ methods  ] %s: GVS_Method in the status messages:%s\n", method.c_str(), seen.c_str());
  EXPECT_GT(measured, 0) << "no status message named a measurement:" << seen;

  // Values after the first 0.5 s. GVS_Velocity and GVS_VelocityXY of one
  // period are sent together: the i-th of each belong to the same estimate.
  ASSERT_EQ(msgs.velocity.size(), msgs.velocity_xy.size());
  const std::int64_t t0 = msgs.velocity.front().t_ns;
  std::size_t counted = 0, valid = 0, fresh_and_good = 0, fresh_and_good_valid = 0, rule_broken = 0;
  double speed_sum = 0.0, dir_min = 1e9, dir_max = -1e9;
  for (std::size_t i = 0; i < msgs.velocity.size(); ++i) {
    const testing::LoggedMessage& m = msgs.velocity[i];
    if (m.t_ns - t0 < 500 * drivers::kNsPerMs) continue;
    ++counted;
    const auto& v = m.decoded.velocity;
    const auto& xy = msgs.velocity_xy[i].decoded.xy;
    // gvsd's defaults: stale after 50 ms, min quality 0.3. GVS_Quality is
    // sent in whole percent, so 29-31 % may be either side of the limit.
    const bool any_valid = v.valid || v.speed_valid || v.direction_valid || v.yaw_rate_valid || xy.valid;
    if (any_valid && !(xy.age_ms <= 50 && v.quality_pct >= 29.0)) {
      ++rule_broken;
      ADD_FAILURE() << "period " << i << ": a Valid bit set with age " << xy.age_ms << " ms, quality "
                    << v.quality_pct << " %";
    }
    if (xy.age_ms <= 50 && v.quality_pct >= 31.0) {
      ++fresh_and_good;
      fresh_and_good_valid += v.valid ? 1 : 0;
    }
    if (!v.valid) continue;
    ++valid;
    speed_sum += v.speed_mps;
    dir_min = std::min(dir_min, v.direction_deg);
    dir_max = std::max(dir_max, v.direction_deg);
  }
  const double valid_fraction = static_cast<double>(valid) / static_cast<double>(counted);
  const double mean_speed = valid > 0 ? speed_sum / static_cast<double>(valid) : 0.0;
  ::testing::Test::RecordProperty("median_period_ms", std::to_string(median));
  ::testing::Test::RecordProperty("p99_deviation_ms", std::to_string(p99));
  ::testing::Test::RecordProperty("valid_fraction", std::to_string(valid_fraction));
  ::testing::Test::RecordProperty("mean_speed_mps", std::to_string(mean_speed));
  std::printf("[ figures  ] %s: median period %.4f ms, p99 |deviation| %.3f ms, valid %.1f %%, mean speed %.3f m/s, "
              "direction %.2f .. %.2f deg\n",
              method.c_str(), median, p99, 100.0 * valid_fraction, mean_speed, dir_min, dir_max);
  // Never valid when stale or doubtful; and a fresh, good estimate is not
  // held back (the plausibility gate has nothing to reject on sim:sine).
  EXPECT_EQ(rule_broken, 0u);
  EXPECT_GE(static_cast<double>(fresh_and_good_valid), 0.95 * static_cast<double>(fresh_and_good));
  if (pace == Pace::Camera) {
    EXPECT_GE(valid_fraction, 0.95) << "health: " << slurp(c.err);
  } else {
    // Even a 5 fps render leaves a fresh estimate in some periods; the
    // values below need a few dozen.
    EXPECT_GE(valid, 50u) << "health: " << slurp(c.err);
  }
  EXPECT_NEAR(mean_speed, kSineSpeedMps, 0.02 * kSineSpeedMps);
  EXPECT_NEAR(dir_max, 8.0, 1.0);
  EXPECT_NEAR(dir_min, -8.0, 1.0);
  fs::remove(log);
}

/// A log of `n` messages on a 20 ms grid, each moved by `late_ms(k)`.
template <class Late>
std::vector<testing::LoggedMessage> grid_log(std::size_t n, const Late& late_ms) {
  std::vector<testing::LoggedMessage> log(n);
  for (std::size_t k = 0; k < n; ++k) {
    log[k].t_ns = static_cast<std::int64_t>((20.0 * static_cast<double>(k) + late_ms(k)) * 1e6);
  }
  return log;
}

// The schedule check of the acceptance run tells load from a broken
// schedule: late single messages pass, drift and skipped periods do not.
TEST(ScheduleHold, LatenessOfSingleMessagesKeepsThePhase) {
  const auto hold = testing::schedule_hold(grid_log(500, [](std::size_t k) { return k % 7 == 3 ? 15.0 : 0.2; }), 20.0);
  EXPECT_EQ(hold.whole_periods, 0);
  EXPECT_NEAR(hold.off_grid_ms, 0.0, 1e-6);
}

TEST(ScheduleHold, ASkippedPeriodMovesThePhaseByOnePeriod) {
  const auto hold = testing::schedule_hold(grid_log(500, [](std::size_t k) { return k >= 250 ? 20.0 : 0.0; }), 20.0);
  EXPECT_EQ(hold.whole_periods, 1);
  EXPECT_NEAR(hold.off_grid_ms, 0.0, 1e-6);
}

TEST(ScheduleHold, ARelativeScheduleDriftsOffTheGrid) {
  // Sleeping 20 ms after each send: the send's own 10 us add up.
  const auto hold =
      testing::schedule_hold(grid_log(500, [](std::size_t k) { return 0.01 * static_cast<double>(k); }), 20.0);
  EXPECT_GT(std::fabs(hold.off_grid_ms), 2.0);
}

// With the real estimator on sim:sine, gvsd's built-in defaults (double-pulse
// strobe, closed loop). The live simulator renders as fast as spare CPU
// allows (25-30 fps on an idle 2-core machine, 12-18 fps beside the rest of
// the suite): what is checked is that each period is valid exactly when its
// estimate is fresh and good, and the values of the valid ones.
TEST(GvsdMustShow, SimSine10sWithGvsEstimator) { must_show_run("gvs", "sim:sine", Pace::CpuBound); }

// The acceptance figures with the gvs estimator on a camera that keeps its
// 60 fps: sim:sine rendered beforehand by `gvs sim` (512x384 px, double-pulse
// strobe planned in closed loop by the exposure controller, as on the car)
// and replayed by gvsd at the frames' own pace.
TEST(GvsdMustShow, ReplayedSineWithGvsEstimatorAt60Fps) {
  const fs::path dir = temp_dir() / "sine_double_pulse";
  const std::string cmd = std::string(GVS_BINARY) + " sim --scenario sine --exposure double-pulse --seconds 10.6 --out " +
                          dir.string() + " > " + (temp_dir() / "gvs_sim.out").string() + " 2>&1";
  ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;
  must_show_run("gvs", "replay:" + dir.string(), Pace::Camera);
  fs::remove_all(dir);
}

// With the source's truth in place of the estimator: the daemon's own part
// (timing, packing, staleness) of the same figures.
TEST(GvsdMustShow, SimSine10sWithTruth) { must_show_run("truth", "sim:sine", Pace::CpuBound); }

/// A 10 s replay dataset (small frames), so stopping is not held up by the
/// simulator's render of a frame, which cannot be interrupted (50-90 ms on
/// a loaded 2-core machine): the car's camera source has no such render.
/// The run `sc` written as a dataset with truth (and its lasers in
/// camera.json), every frame exposed with `plan` when one is given.
void write_dataset(const fs::path& dir, const drivers::SimulatorConfig& sc,
                   const std::optional<core::ExposurePlan>& plan = std::nullopt) {
  drivers::Simulator sim(sc);
  if (plan) sim.set_exposure(*plan);
  drivers::CameraInfo cam;
  cam.geometry = sc.camera;
  if (sc.lasers.enabled()) {
    cam.height_mm = sc.camera_height_mm;
    cam.lasers = sc.lasers;
  }
  drivers::DatasetWriter writer(dir, cam, true);
  drivers::SimFrame f;
  while (sim.next(f)) {
    writer.write_frame(f.gray, f.record);
    writer.write_truth(f.truth);
  }
}

/// `seconds` of sim:sine at 128x96 px written as a dataset with truth.
void write_sine_dataset(const fs::path& dir, double seconds) {
  drivers::SimulatorConfig sc;
  sc.scenario = "sine";
  sc.seconds = seconds;
  sc.camera.width_px = 128;
  sc.camera.height_px = 96;
  write_dataset(dir, sc);
}

fs::path replay_dataset() {
  const fs::path dir = temp_dir() / "replay_ds";
  if (!fs::exists(dir / "truth.csv")) write_sine_dataset(dir, 10.0);
  return dir;
}

TEST(Gvsd, SigtermStopsCleanlyWithin100Milliseconds) {
  const fs::path log = temp_dir() / "sigterm.log";
  const Child c = spawn({"--source", "replay:" + replay_dataset().string(), "--can", "candump:" + log.string()},
                        "sigterm");
  // Wait until it runs (CAN lines appear), then a little more.
  const std::int64_t deadline = drivers::mono_now_ns() + 30 * drivers::kNsPerS;
  while (read_candump_log(log.string()).velocity.size() < 10 && drivers::mono_now_ns() < deadline) {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  std::this_thread::sleep_for(std::chrono::milliseconds(200));
  const std::int64_t t0 = drivers::mono_now_ns();
  kill(c.pid, SIGTERM);
  const int code = wait_exit(c);
  const double took_ms = static_cast<double>(drivers::mono_now_ns() - t0) / 1e6;
  EXPECT_EQ(code, 0) << slurp(c.err);
  EXPECT_LT(took_ms, 100.0);
  const auto msgs = read_candump_log(log.string());
  ASSERT_FALSE(msgs.status.empty());
  EXPECT_EQ(msgs.status.back().decoded.status_msg.state, can::SensorState::Stopping);
  EXPECT_NE(slurp(c.err).find("stopped (SIGTERM)"), std::string::npos) << slurp(c.err);
  std::printf("[ figures  ] SIGTERM to exit: %.1f ms\n", took_ms);
}

// Every thread blocks the stop and reload signals, also those gvsd does not
// start itself (a replay's decoder here): the kernel gives a process's signal
// to any thread that does not block it, and SIGTERM's default action there
// would end gvsd without its Stopping message.
TEST(Gvsd, EveryThreadBlocksTheStopAndReloadSignals) {
  const fs::path log = temp_dir() / "sigmask.log";
  const fs::path cfg = write_config("sigmask.toml", "[source]\nreplay_window_mb = 1\n");  // the decoder keeps running
  const Child c = spawn({"--config", cfg.string(), "--source", "replay:" + replay_dataset().string(), "--can",
                         "candump:" + log.string()},
                        "sigmask");
  const std::int64_t deadline = drivers::mono_now_ns() + 30 * drivers::kNsPerS;
  while (read_candump_log(log.string()).velocity.size() < 10 && drivers::mono_now_ns() < deadline) {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  constexpr unsigned long long kStopAndReload = (1ULL << (SIGTERM - 1)) | (1ULL << (SIGINT - 1)) | (1ULL << (SIGHUP - 1));
  int threads = 0;
  for (const auto& task : fs::directory_iterator("/proc/" + std::to_string(c.pid) + "/task")) {
    // The main thread takes them: sigtimedwait unblocks them while it waits.
    if (task.path().filename() == std::to_string(c.pid)) continue;
    std::ifstream status(task.path() / "status");
    std::string line;
    while (std::getline(status, line)) {
      if (line.rfind("SigBlk:", 0) != 0) continue;
      const unsigned long long blocked = std::stoull(line.substr(7), nullptr, 16);
      EXPECT_EQ(blocked & kStopAndReload, kStopAndReload) << "thread " << task.path().filename() << ": " << line;
      ++threads;
    }
  }
  EXPECT_GE(threads, 4) << "capture, processing, sender and the replay's decoder";
  kill(c.pid, SIGTERM);
  EXPECT_EQ(wait_exit(c), 0) << slurp(c.err);
  EXPECT_NE(slurp(c.err).find("stopped (SIGTERM)"), std::string::npos) << slurp(c.err);
}

TEST(Gvsd, ReplayWithBrokenFramesPlaysOnAndCountsThem) {
  // A 1 s recording with one truncated and one missing frame file: gvsd
  // names both at start-up, plays the rest at its pace, counts 2 rejected.
  const fs::path dir = temp_dir() / "broken_ds";
  fs::remove_all(dir);
  write_sine_dataset(dir, 1.0);
  const drivers::DatasetReader reader(dir);
  ASSERT_GT(reader.frames().size(), 30u);
  fs::resize_file(dir / reader.frames()[10].file, 40);
  fs::remove(dir / reader.frames()[20].file);
  const fs::path log = temp_dir() / "broken.log";
  const Child c = spawn({"--source", "replay:" + dir.string(), "--can", "candump:" + log.string()}, "broken");
  EXPECT_EQ(wait_exit(c), 0) << slurp(c.err);
  const std::string err = slurp(c.err);
  EXPECT_NE(err.find("frame " + std::to_string(reader.frames()[10].index) + " gets no estimate"), std::string::npos)
      << err;
  EXPECT_NE(err.find("frame " + std::to_string(reader.frames()[20].index) + " gets no estimate"), std::string::npos)
      << err;
  EXPECT_NE(err.find("stopped (end of the source)"), std::string::npos) << err;
  EXPECT_NE(err.find("rejected 2"), std::string::npos) << err;
  EXPECT_NE(err.find("[unreadable 2"), std::string::npos) << "both counted as unreadable: " << err;
  const auto msgs = read_candump_log(log.string());
  EXPECT_GT(msgs.velocity.size(), 40u) << "played on to the end";
}

TEST(Gvsd, SigintStopsToo) {
  const Child c = spawn({"--source", "sim:const", "--can", "candump:" + (temp_dir() / "sigint.log").string()}, "sigint");
  std::this_thread::sleep_for(std::chrono::milliseconds(1500));
  kill(c.pid, SIGINT);
  EXPECT_EQ(wait_exit(c), 0);
  EXPECT_NE(slurp(c.err).find("stopped (SIGINT)"), std::string::npos) << slurp(c.err);
}

/// A datagram socket standing in for systemd's notify socket.
class NotifySocket {
 public:
  NotifySocket() {
    path_ = (temp_dir() / "notify.sock").string();
    fs::remove(path_);
    fd_ = socket(AF_UNIX, SOCK_DGRAM | SOCK_CLOEXEC | SOCK_NONBLOCK, 0);
    sockaddr_un addr{};
    addr.sun_family = AF_UNIX;
    std::snprintf(addr.sun_path, sizeof(addr.sun_path), "%s", path_.c_str());
    if (bind(fd_, reinterpret_cast<sockaddr*>(&addr), sizeof(addr)) != 0) ADD_FAILURE() << "bind " << path_;
  }
  ~NotifySocket() { close(fd_); }
  [[nodiscard]] const std::string& path() const { return path_; }
  std::vector<std::string> drain() {
    std::vector<std::string> out;
    char buf[4096];
    for (;;) {
      const ssize_t n = recv(fd_, buf, sizeof(buf), 0);
      if (n <= 0) break;
      out.emplace_back(buf, static_cast<std::size_t>(n));
    }
    return out;
  }

 private:
  std::string path_;
  int fd_ = -1;
};

// Memory is locked as it is touched (MCL_ONFAULT, the default), and the
// processing thread runs the estimator over made-up frames of every kind
// before the first real one (warm_up.hpp): no real-time thread faults while
// frames flow, from the first health line on.
TEST(Gvsd, RealTimeThreadsDoNotFaultOnceTheEstimatorIsWarm) {
  const Child c = spawn({"--source", "replay:" + replay_dataset().string(), "--can", "candump:/dev/null", "--run-for",
                         "5", "--config", write_config("faults.toml", "[log]\nhealth_interval_s = 1\n").string()},
                        "faults");
  ASSERT_EQ(wait_exit(c), 0) << slurp(c.err);
  const std::string err = slurp(c.err);
  std::istringstream lines(err);
  std::string line;
  std::vector<std::vector<long>> totals;  // per health line: capture, processing, sender
  const std::regex fault(R"(page faults (\d+) \(\+\d+\))");
  while (std::getline(lines, line)) {
    if (line.find("health:") == std::string::npos) continue;
    std::vector<long> t;
    for (auto m = std::sregex_iterator(line.begin(), line.end(), fault); m != std::sregex_iterator(); ++m) {
      t.push_back(std::stol((*m)[1].str()));
    }
    ASSERT_EQ(t.size(), 3u) << "capture, processing and sender each show their page faults: " << line;
    totals.push_back(t);
  }
  ASSERT_GE(totals.size(), 3u) << err;
  EXPECT_EQ(totals.back(), (std::vector<long>{0, 0, 0})) << err;
}

TEST(Gvsd, NotifiesSystemdReadyStatusWatchdogStopping) {
  NotifySocket sock;
  const Child c = spawn({"--source", "sim:const", "--can", "candump:" + (temp_dir() / "notify.log").string(),
                         "--run-for", "2", "--config",
                         write_config("notify.toml", "[log]\nhealth_interval_s = 0.5\n").string()},
                        "notify", {{"NOTIFY_SOCKET", sock.path()}, {"WATCHDOG_USEC", "200000"}});
  // Read while it runs, as systemd does (a full datagram queue would block sd_notify).
  std::vector<std::string> messages;
  std::atomic<bool> exited{false};
  std::thread reader([&] {
    while (!exited.load()) {
      for (std::string& m : sock.drain()) messages.push_back(std::move(m));
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
  });
  const int code = wait_exit(c);
  exited = true;
  reader.join();
  for (std::string& m : sock.drain()) messages.push_back(std::move(m));
  ASSERT_EQ(code, 0) << slurp(c.err);
  int ready = 0, watchdog = 0, status = 0, stopping = 0;
  for (const std::string& m : messages) {
    ready += m.find("READY=1") != std::string::npos ? 1 : 0;
    watchdog += m.find("WATCHDOG=1") != std::string::npos ? 1 : 0;
    status += m.find("STATUS=") != std::string::npos ? 1 : 0;
    stopping += m.find("STOPPING=1") != std::string::npos ? 1 : 0;
  }
  EXPECT_EQ(ready, 1);
  EXPECT_GE(watchdog, 10) << "pinged every 100 ms while all threads progress";
  EXPECT_GE(status, 3);
  EXPECT_EQ(stopping, 1);
}

TEST(Gvsd, SighupReloadsWhatCanBeReloaded) {
  const fs::path cfg =
      write_config("reload.toml", "[source]\nuri = \"sim:const\"\n[can]\nstaleness_limit_ms = 50\n");
  const Child c = spawn({"--config", cfg.string(), "--can", "candump:" + (temp_dir() / "reload.log").string()},
                        "reload");
  std::this_thread::sleep_for(std::chrono::milliseconds(1500));
  write_config("reload.toml", "[source]\nuri = \"sim:sine\"\n[can]\nstaleness_limit_ms = 20\n[log]\nlevel = \"debug\"\n");
  kill(c.pid, SIGHUP);
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  write_config("reload.toml", "[source]\nuri = \"sim:const\"\n[can]\nstaleness_limit_ms = \"bad\"\n");
  kill(c.pid, SIGHUP);
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  kill(c.pid, SIGTERM);
  EXPECT_EQ(wait_exit(c), 0);
  const std::string err = slurp(c.err);
  EXPECT_NE(err.find("SIGHUP: reloaded"), std::string::npos) << err;
  EXPECT_NE(err.find("staleness limit 20 ms"), std::string::npos) << err;
  // Each key the table marks reloadable is logged as it is applied.
  EXPECT_NE(err.find("SIGHUP: applying can.staleness_limit_ms = 20.0 (was 50.0)"), std::string::npos) << err;
  EXPECT_NE(err.find("SIGHUP: applying log.level = \"debug\" (was \"info\")"), std::string::npos) << err;
  EXPECT_NE(err.find("source.uri changed"), std::string::npos) << err;
  EXPECT_NE(err.find("SIGHUP: keeping the running configuration"), std::string::npos) << err;
  EXPECT_NE(err.find("staleness_limit_ms must be a number"), std::string::npos) << err;
}

// [height] source = "lasers": a replayed head with laser dots (the
// simulator's design beams, written to camera.json) puts the height the dots
// measure on the bus as GVS_RideHeight, and scales the speed with it.
TEST(Gvsd, LaserDotsOfTheFramesGoOutAsRideHeight) {
  const fs::path dir = temp_dir() / "lasers_ds";
  drivers::SimulatorConfig sc;
  sc.scenario = "const";
  sc.seconds = 1.5;
  sc.lasers = core::design_laser_geometry(sc.camera, sc.camera_height_mm);
  core::ExposurePlan double_pulse;  // 20 us pulses 400 us apart: the strobe gvsd plans at this speed
  double_pulse.pulse_count = 2;
  double_pulse.pulses[0] = {0.0, 20.0};
  double_pulse.pulses[1] = {400.0, 20.0};
  double_pulse.exposure_us = 420.0;
  write_dataset(dir, sc, double_pulse);
  const fs::path cfg =
      write_config("lasers.toml", "[height]\nsource = \"lasers\"\nlasers_file = \"" + (dir / "camera.json").string() + "\"\n");
  const fs::path log = temp_dir() / "lasers.log";
  const Child c = spawn({"--config", cfg.string(), "--source", "replay:" + dir.string(), "--can", "candump:" + log.string()},
                        "lasers");
  ASSERT_EQ(wait_exit(c), 0) << slurp(c.err);
  EXPECT_NE(slurp(c.err).find("speed scale: height, pitch and roll from the laser dots"), std::string::npos)
      << slurp(c.err);
  const auto msgs = read_candump_log(log.string());
  ASSERT_GE(msgs.ride_height.size(), 50u);
  // Flat ground at the nominal height. The dots are not found in every frame
  // (docs/accuracy.md, "Speed with the laser dots' height": 97-99 % of
  // frames); a message without a fresh height says so (HeightValid 0), and
  // one whose four dots disagree by enough to hide a wrong tilt carries the
  // height without it (PitchValid and RollValid 0).
  std::vector<double> height_err_mm, tilt_err_deg;
  for (const auto& m : msgs.ride_height) {
    const can::RideHeightMsg& r = m.decoded.ride;
    if (!r.height_valid) {
      EXPECT_FALSE(r.pitch_valid || r.roll_valid);
      continue;
    }
    EXPECT_EQ(r.scale_source, can::ScaleSourceCode::LaserDots);
    height_err_mm.push_back(std::fabs(r.height_mm - 60.0));
    if (r.pitch_valid) tilt_err_deg.push_back(std::fabs(r.pitch_deg));
    if (r.roll_valid) tilt_err_deg.push_back(std::fabs(r.roll_deg));
  }
  EXPECT_GE(height_err_mm.size(), msgs.ride_height.size() * 8 / 10);
  EXPECT_GE(tilt_err_deg.size(), 2 * height_err_mm.size() * 8 / 10);  // a pitch and a roll each
  EXPECT_LT(quantile(height_err_mm, 0.5), 0.05);
  EXPECT_LT(quantile(height_err_mm, 1.0), 0.5);
  EXPECT_LT(quantile(tilt_err_deg, 0.5), 0.25);
  EXPECT_LT(quantile(tilt_err_deg, 0.9), 0.6);
  std::size_t scaled = 0;
  for (const auto& m : msgs.velocity_xy) scaled += m.decoded.xy.scale_source == can::ScaleSourceCode::LaserDots ? 1 : 0;
  EXPECT_GE(scaled, msgs.velocity_xy.size() * 8 / 10);
  fs::remove_all(dir);
}

// The live simulated camera carries the lasers gvsd is told to read, so a
// desk run shows the ride height (here with the simulator's heave).
TEST(Gvsd, SimulatedHeadCarriesTheConfiguredLasers) {
  const fs::path lasers = temp_dir() / "design_lasers.json";
  core::CameraGeometry camera;
  std::ofstream(lasers) << drivers::laser_geometry_json_text(core::design_laser_geometry(camera, 60.0)) << "\n";
  const fs::path cfg = write_config("sim_lasers.toml", "[source]\nsim_body = \"heave\"\n[height]\nsource = \"lasers\"\n"
                                                       "lasers_file = \"" + lasers.string() + "\"\n");
  const fs::path log = temp_dir() / "sim_lasers.log";
  const Child c = spawn({"--config", cfg.string(), "--source", "sim:const", "--run-for", "3", "--can", "candump:" + log.string()},
                        "sim_lasers");
  ASSERT_EQ(wait_exit(c), 0) << slurp(c.err);
  const auto msgs = read_candump_log(log.string());
  std::size_t measured = 0;
  for (const auto& m : msgs.ride_height) {
    const can::RideHeightMsg& r = m.decoded.ride;
    if (!r.height_valid) continue;
    ++measured;
    EXPECT_EQ(r.scale_source, can::ScaleSourceCode::LaserDots);
    EXPECT_NEAR(r.height_mm, 60.0, 5.5);  // heave: +-5 mm
  }
  EXPECT_GE(measured, 1u) << "no GVS_RideHeight with a measured height in " << msgs.ride_height.size();
}

TEST(Gvsd, BadConfigurationStopsStartUpNamingKeyAndRange) {
  const fs::path cfg = write_config("bad.toml", "[threads.capture]\npriority = 200\n");
  const Child c = spawn({"--config", cfg.string()}, "badconfig");
  EXPECT_EQ(wait_exit(c), 1);
  const std::string err = slurp(c.err);
  EXPECT_NE(err.find("[threads.capture] priority = 200 is out of range"), std::string::npos) << err;
  EXPECT_NE(err.find("0 .. 99"), std::string::npos) << err;
  EXPECT_TRUE(slurp(c.out).empty());
}

// --check-config runs start-up's checks: what it accepts, start-up does not
// refuse for a reason the file shows; devices are not opened.
TEST(Gvsd, CheckConfigRefusesWhatStartUpRefuses) {
  const std::pair<const char*, const char*> cases[] = {
      {"[estimator]\nmethod = \"foo\"\n", "[estimator] method = \"foo\" is not allowed"},
      {"[source]\nuri = \"sim:nonexistent\"\n", "unknown scenario 'nonexistent'"},
      {"[height]\nsource = \"lasers\"\n", "[height] source = \"lasers\" needs lasers_file"},
      {"[height]\nsource = \"lasers\"\nlasers_file = \"/nonexistent/lasers.json\"\n",
       "[height] lasers_file: /nonexistent/lasers.json: cannot read"},
  };
  for (const auto& [toml, want] : cases) {
    const fs::path cfg = write_config("refused.toml", toml);
    const Child check = spawn({"--check-config", "--config", cfg.string()}, "check_refused");
    EXPECT_EQ(wait_exit(check), 1) << toml;
    EXPECT_NE(slurp(check.err).find(want), std::string::npos) << slurp(check.err);
    EXPECT_EQ(slurp(check.out).find("configuration OK"), std::string::npos) << slurp(check.out);
    const Child start = spawn({"--config", cfg.string(), "--can", "candump:/dev/null"}, "start_refused");
    EXPECT_EQ(wait_exit(start), 1) << toml;
    EXPECT_NE(slurp(start.err).find(want), std::string::npos) << slurp(start.err);
  }
  // No camera and no such CAN interface here: start-up would fail opening
  // them, the check does not open them.
  const Child ok = spawn({"--check-config", "--source", "libcamera:0", "--can", "socketcan:gvsnone0"}, "check_ok");
  EXPECT_EQ(wait_exit(ok), 0) << slurp(ok.err);
  EXPECT_NE(slurp(ok.out).find("configuration OK (source libcamera:0, CAN socketcan:gvsnone0"), std::string::npos)
      << slurp(ok.out);
}

TEST(Gvsd, PrintsTheExampleFileAndTheReference) {
  const Child example = spawn({"--print-example-config"}, "print_example");
  EXPECT_EQ(wait_exit(example), 0);
  EXPECT_EQ(slurp(example.out), slurp(fs::path(GVSD_SOURCE_DIR) / "systemd" / "gvsd.toml"));
  const Child reference = spawn({"--print-config-reference"}, "print_reference");
  EXPECT_EQ(wait_exit(reference), 0);
  const std::string md = slurp(reference.out);
  EXPECT_NE(md.find("| `staleness_limit_ms` | number | `50.0` | 1 .. 1000 ms | reload |"), std::string::npos) << md;
  EXPECT_NE(slurp(fs::path(GVSD_SOURCE_DIR) / "docs" / "daemon.md").find(md), std::string::npos)
      << "docs/daemon.md holds the reference as printed";
}

TEST(Gvsd, RefusesLibcameraAndUnknownSourcesClearly) {
  // This machine has no camera: the libcamera source stops start-up saying what to check.
  const Child a = spawn({"--source", "libcamera:0"}, "libcamera");
  EXPECT_EQ(wait_exit(a), 1);
  const std::string a_err = slurp(a.err);
  EXPECT_TRUE(a_err.find("no camera found") != std::string::npos ||
              a_err.find("built without libcamera") != std::string::npos)
      << a_err;
  const Child b = spawn({"--can", "carrier-pigeon:x"}, "badcan");
  EXPECT_EQ(wait_exit(b), 1);
  EXPECT_NE(slurp(b.err).find("carrier-pigeon"), std::string::npos) << slurp(b.err);
}

TEST(Gvsd, JournalFormatUnderSystemd) {
  const Child c = spawn({"--source", "sim:const", "--can", "candump:" + (temp_dir() / "journal.log").string(),
                         "--run-for", "0.5"},
                        "journal", {{"INVOCATION_ID", "0123456789abcdef"}});
  ASSERT_EQ(wait_exit(c), 0);
  const std::string err = slurp(c.err);
  std::istringstream lines(err);
  std::string line;
  int n = 0;
  while (std::getline(lines, line)) {
    ++n;
    ASSERT_GE(line.size(), 3u);
    EXPECT_EQ(line[0], '<') << line;
    EXPECT_TRUE(line[1] >= '0' && line[1] <= '7') << line;
    EXPECT_EQ(line[2], '>') << line;
  }
  EXPECT_GE(n, 2);
  EXPECT_EQ(err.find('\x1b'), std::string::npos) << "no colours in the journal";
  EXPECT_NE(err.find("<6>gvsd: source sim:const"), std::string::npos) << err;
}

// README's first command: no arguments on a desk = sim:sine, candump lines on stdout.
TEST(Gvsd, NoArgumentsRunsSimSineToStdout) {
  const Child c = spawn({}, "noargs");
  std::this_thread::sleep_for(std::chrono::milliseconds(2500));
  kill(c.pid, SIGTERM);
  EXPECT_EQ(wait_exit(c), 0);
  const auto msgs = read_candump_log(c.out.string());
  EXPECT_EQ(msgs.unparsed, 0u);
  EXPECT_GE(msgs.velocity.size(), 50u);
  EXPECT_NE(slurp(c.err).find("source sim:sine"), std::string::npos);
}

}  // namespace
}  // namespace gvs::daemon
