// gvsd latency benchmark (not a timed test; docs/performance.md).
//
// Runs the real pipeline in-process (sim:SCENARIO, the configured estimator,
// candump to a file, the configured RT priorities) for N seconds and reports
//   - frame-to-CAN latency: frame received by the capture thread -> first CAN
//     send carrying its estimate (includes the wait for the next 20 ms slot),
//   - the same after the first second (the slots locked to the frames and
//     the estimator past its first frames: the steady state),
//   - frame-to-publish latency: capture -> estimate in the seqlock,
//   - sender wake-up lateness: clock_nanosleep(TIMER_ABSTIME) return - target,
// each as median / p99 / max, and runs `cyclictest` beside it for the same
// time as the machine's reference wake-up latency.
//
//   gvsd_latency_bench [SECONDS=30] [ESTIMATOR=gvs] [SCENARIO=sine] [FPS=60] [PERIOD_MS=20] [free|align]
//
// `align` sets [can] align_to_frames (the frame rate must then be a multiple
// or a divisor of the CAN rate, e.g. 100 fps at 20 ms). A SCENARIO with a
// colon is a source URI (`replay:DIR`: the dataset's own rate; FPS is then
// ignored).
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "gvs/can/sink.hpp"
#include "gvs/drivers/clock.hpp"
#include "gvs/daemon/source_factory.hpp"
#include "gvs/daemon/pipeline.hpp"

using namespace gvs::daemon;

namespace {

struct Stats {
  double median = 0, p99 = 0, max = 0;
  std::size_t n = 0;
};

Stats stats_us(std::vector<std::int64_t> ns) {
  Stats s;
  s.n = ns.size();
  if (ns.empty()) return s;
  std::sort(ns.begin(), ns.end());
  auto at = [&](double q) { return static_cast<double>(ns[static_cast<std::size_t>(q * static_cast<double>(ns.size() - 1))]) / 1000.0; };
  s.median = at(0.5);
  s.p99 = at(0.99);
  s.max = static_cast<double>(ns.back()) / 1000.0;
  return s;
}

void print(const char* what, const Stats& s) {
  std::printf("%-34s n=%-6zu median %9.1f us   p99 %9.1f us   max %9.1f us\n", what, s.n, s.median, s.p99, s.max);
}

/// cyclictest's histogram (-h) into median / p99 / max, in us.
Stats parse_cyclictest(const std::string& text) {
  std::vector<std::pair<long, long>> hist;
  long max_seen = 0;
  std::istringstream in(text);
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty()) continue;
    if (line[0] >= '0' && line[0] <= '9') {
      long us = 0, count = 0;
      if (std::sscanf(line.c_str(), "%ld %ld", &us, &count) == 2 && count > 0) hist.emplace_back(us, count);
    } else if (line.rfind("# Max Latencies:", 0) == 0) {
      std::sscanf(line.c_str() + 16, "%ld", &max_seen);
    }
  }
  Stats s;
  long total = 0;
  for (auto& [us, c] : hist) total += c;
  s.n = static_cast<std::size_t>(total);
  long acc = 0;
  bool have_median = false;
  for (auto& [us, c] : hist) {
    acc += c;
    if (!have_median && acc * 2 >= total) {
      s.median = static_cast<double>(us);
      have_median = true;
    }
    if (acc * 100 >= total * 99) {
      s.p99 = static_cast<double>(us);
      break;
    }
  }
  s.max = static_cast<double>(max_seen);
  return s;
}

}  // namespace

int main(int argc, char** argv) {
  const double seconds = argc > 1 ? std::atof(argv[1]) : 30.0;
  const std::string method = argc > 2 ? argv[2] : "gvs";
  const std::string scenario = argc > 3 ? argv[3] : "sine";
  const double fps = argc > 4 ? std::atof(argv[4]) : 60.0;
  const int period_ms = argc > 5 ? std::atoi(argv[5]) : 20;
  const bool align = argc > 6 && std::string(argv[6]) == "align";

  DaemonConfig c;  // default priorities: capture 80, processing 70, sender 90
  c.source_uri = scenario.find(':') == std::string::npos ? "sim:" + scenario : scenario;
  c.estimator_method = method;
  c.sim_fps = fps;
  c.period_ms = period_ms;
  c.status_period_ms = 100 / period_ms * period_ms;
  c.align_to_frames = align;
  const std::string log = (std::filesystem::temp_directory_path() / "gvsd_bench.log").string();
  const std::string cyc_out = (std::filesystem::temp_directory_path() / "gvsd_bench_cyclictest.txt").string();

  // cyclictest beside us (rt-tests 2.x: clock_nanosleep is its default): one
  // thread, SCHED_FIFO 90 (the sender's priority), 1 ms interval, histogram in us.
  const long loops = static_cast<long>(seconds * 1000.0);
  const pid_t cyc = fork();
  if (cyc == 0) {
    std::freopen(cyc_out.c_str(), "w", stdout);
    std::freopen("/dev/null", "w", stderr);
    const std::string l = std::to_string(loops);
    execlp("cyclictest", "cyclictest", "-m", "-q", "-p", "90", "-i", "1000", "-h", "20000", "-l", l.c_str(),
           static_cast<char*>(nullptr));
    _exit(127);
  }

  lock_all_memory(c.lock_on_fault);
  auto source = make_frame_source(c);
  auto estimator = make_frame_estimator(method, source->geometry());
  PipelineHooks hooks;
  hooks.record_capacity = static_cast<std::size_t>(seconds * 1000.0) + 1000;
  Pipeline p(c, std::move(source), std::move(estimator), gvs::can::open_sink("candump:" + log), hooks);
  p.start();
  std::this_thread::sleep_for(std::chrono::duration<double>(seconds));
  p.request_stop();
  p.join();

  int status = 0;
  waitpid(cyc, &status, 0);
  std::ifstream in(cyc_out);
  std::stringstream text;
  text << in.rdbuf();

  const SenderRecords& r = p.records();
  const HealthSnapshot h = snapshot(p.counters());
  std::printf("gvsd_latency_bench: %.0f s, %s at %.0f fps, estimator %s, CAN every %d ms, slots %s, realtime %s, "
              "load: ",
              seconds, c.source_uri.c_str(), p.source().nominal_fps(), method.c_str(), period_ms,
              align ? "aligned to the frames" : "free", p.realtime() ? "SCHED_FIFO" : "no");
  std::fflush(stdout);
  std::system("cut -d' ' -f1-3 /proc/loadavg");
  print("frame-to-CAN (capture->send)", stats_us({r.frame_to_can_ns.begin(), r.frame_to_can_ns.begin() + static_cast<std::ptrdiff_t>(r.estimates)}));
  // The first 1000 / period_ms estimates: the first second where the camera
  // is at least as fast as the CAN rate (each slot carries a new estimate).
  const auto first_second = std::min<std::size_t>(r.estimates, static_cast<std::size_t>(1000 / period_ms));
  print("frame-to-CAN after the first second",
        stats_us({r.frame_to_can_ns.begin() + static_cast<std::ptrdiff_t>(first_second),
                  r.frame_to_can_ns.begin() + static_cast<std::ptrdiff_t>(r.estimates)}));
  print("frame-to-publish (capture->seqlock)", stats_us({r.frame_to_publish_ns.begin(), r.frame_to_publish_ns.begin() + static_cast<std::ptrdiff_t>(r.estimates)}));
  print("sender wake-up lateness", stats_us({r.wakeup_late_ns.begin(), r.wakeup_late_ns.begin() + static_cast<std::ptrdiff_t>(r.wakeups)}));
  const Stats cyclic = parse_cyclictest(text.str());
  if (WIFEXITED(status) && WEXITSTATUS(status) == 0 && cyclic.n > 0) {
    print("cyclictest wake-up latency (1 ms)", cyclic);
  } else {
    std::printf("cyclictest did not run or printed no histogram (apt-get install rt-tests), status %d\n", status);
  }
  std::printf("frames captured %llu, processed %llu, skipped %llu, dropped %llu, overruns %llu, late wake-ups %llu, "
              "missed %llu, send errors %llu\n",
              static_cast<unsigned long long>(h.frames_captured), static_cast<unsigned long long>(h.frames_processed),
              static_cast<unsigned long long>(h.frames_skipped), static_cast<unsigned long long>(h.frames_dropped),
              static_cast<unsigned long long>(h.ring_overruns),
              static_cast<unsigned long long>(h.late_wakeups), static_cast<unsigned long long>(h.missed_ticks),
              static_cast<unsigned long long>(h.send_errors));
  std::filesystem::remove(log);
  return 0;
}
