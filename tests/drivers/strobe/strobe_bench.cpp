// gvs_strobe_bench: fires N frames of a plan on GPIO lines and prints the
// achieved edge timing (docs/hardware.md, "Light and trigger"):
//   gvs_strobe_bench --chip gpiochip0 --led-line 1 [--trigger-line 0] --plan double --frames 300
// Lateness = time right after the set-value call returned - due time. Pulse
// duration and double-pulse separation errors are what the speed sees.
// Ends with "strobe-bench: OK" when no edge came early and no set-value call
// failed; exit 1 otherwise.
#include <sched.h>
#include <sys/mman.h>
#include <time.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "gvs/drivers/gpio_strobe.hpp"

namespace {

std::int64_t now_ns() {
  timespec ts{};
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return static_cast<std::int64_t>(ts.tv_sec) * 1'000'000'000 + ts.tv_nsec;
}

struct Stats {
  double median = 0, p99 = 0, max = 0;
};

Stats stats_us(std::vector<double> v) {
  Stats s;
  if (v.empty()) return s;
  std::sort(v.begin(), v.end());
  s.median = v[v.size() / 2];
  s.p99 = v[std::min(v.size() - 1, static_cast<std::size_t>(std::ceil(0.99 * static_cast<double>(v.size()))) - 1)];
  s.max = v.back();
  return s;
}

void print(const char* what, const std::vector<double>& v) {
  const Stats s = stats_us(v);
  std::printf("  %-34s n %5zu  median %9.1f  p99 %9.1f  max %9.1f us\n", what, v.size(), s.median, s.p99, s.max);
}

[[noreturn]] void usage(const char* why) {
  std::fprintf(stderr,
               "gvs_strobe_bench: %s\nusage: gvs_strobe_bench --chip CHIP --led-line N [--trigger-line N] "
               "[--plan single|double|continuous] [--frames N] [--fps F] [--pulse-us U] [--separation-us U] "
               "[--exposure-us U] [--spin-us U] [--active-low] [--priority P] [--dump-frames N] [--no-warm-up]\n",
               why);
  std::exit(2);
}

}  // namespace

int main(int argc, char** argv) {
  gvs::drivers::StrobeConfig c;
  c.driver = "gpio";
  c.consumer = "gvs_strobe_bench";
  std::string plan_name = "double";
  int frames = 300, priority = 0, dump_frames = 0;
  double fps = 60.0, pulse_us = 20.0, separation_us = 500.0, exposure_us = 3000.0;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto value = [&]() -> const char* {
      if (i + 1 >= argc) usage(("missing value after " + a).c_str());
      return argv[++i];
    };
    if (a == "--chip") c.gpio_chip = value();
    else if (a == "--led-line") c.led_line = std::atoi(value());
    else if (a == "--trigger-line") c.trigger_line = std::atoi(value());
    else if (a == "--plan") plan_name = value();
    else if (a == "--frames") frames = std::atoi(value());
    else if (a == "--fps") fps = std::atof(value());
    else if (a == "--pulse-us") pulse_us = std::atof(value());
    else if (a == "--separation-us") separation_us = std::atof(value());
    else if (a == "--exposure-us") exposure_us = std::atof(value());
    else if (a == "--spin-us") c.spin_us = std::atof(value());
    else if (a == "--active-low") c.active_low = true;
    else if (a == "--no-warm-up") c.warm_up_write = false;
    else if (a == "--priority") priority = std::atoi(value());
    else if (a == "--dump-frames") dump_frames = std::atoi(value());
    else usage(("unknown argument " + a).c_str());
  }
  if (frames < 1 || fps <= 0.0) usage("--frames and --fps must be positive");

  gvs::core::ExposurePlan plan;
  plan.exposure_us = exposure_us;
  if (plan_name == "single") {
    plan.pulse_count = 1;
    plan.pulses[0] = {0.0, pulse_us};
    plan.exposure_us = pulse_us;
  } else if (plan_name == "double") {
    plan.pulse_count = 2;
    plan.pulses[0] = {0.0, pulse_us};
    plan.pulses[1] = {separation_us, pulse_us};
    plan.exposure_us = separation_us + pulse_us;
  } else if (plan_name != "continuous") {
    usage("--plan must be single, double or continuous");
  }

  if (mlockall(MCL_CURRENT | MCL_FUTURE) != 0) std::printf("strobe-bench: mlockall failed (%s)\n", std::strerror(errno));
  if (priority > 0) {
    sched_param p{};
    p.sched_priority = priority;
    if (sched_setscheduler(0, SCHED_FIFO, &p) != 0) {
      std::printf("strobe-bench: SCHED_FIFO %d refused (%s); normal scheduling\n", priority, std::strerror(errno));
    }
  }

  gvs::drivers::GpioStrobe strobe(c);  // throws with the chip/line named
  strobe.arm(plan, 1e6 / fps);
  std::printf("strobe-bench: %s, plan %s (%zu pulse(s) of %.0f us%s, exposure %.0f us), %d frames at %.0f fps, "
              "spin %.0f us%s, priority %d\n",
              strobe.describe().c_str(), plan_name.c_str(), plan.pulse_count, plan.pulse_count ? pulse_us : exposure_us,
              plan.pulse_count == 2 ? (", " + std::to_string(static_cast<int>(separation_us)) + " us apart").c_str() : "",
              plan.exposure_us, frames, fps, c.spin_us, c.warm_up_write ? " with a warm-up write" : "", priority);

  {
    // The spin's resolution: one CLOCK_MONOTONIC read.
    const std::int64_t t0 = now_ns();
    std::int64_t t = t0;
    for (int i = 0; i < 10000; ++i) t = now_ns();
    std::printf("clock_gettime(CLOCK_MONOTONIC): %.2f us per call\n", static_cast<double>(t - t0) / 1e4 / 1e3);
  }
  std::vector<double> late_trigger, late_led_on, late_led_off, duration_err, separation_err;
  std::size_t edges = 0, late_edges = 0, early = 0, errors = 0;
  const auto period_ns = static_cast<std::int64_t>(1e9 / fps);
  std::int64_t start_ns = now_ns() + period_ns;
  for (int f = 0; f < frames; ++f, start_ns += period_ns) {
    const gvs::drivers::FireReport r = strobe.fire(start_ns);
    edges += r.edges;
    late_edges += r.late_edges;
    errors += r.error ? 1 : 0;
    std::int64_t on_ns[gvs::core::ExposurePlan::kMaxPulses]{};
    std::size_t pulse = 0;
    if (f < dump_frames) {
      std::printf("frame %d edges (due after the frame start / lateness, us):", f);
      for (const gvs::drivers::StrobeEdge& e : strobe.last_edges()) {
        std::printf(" %s%s %.0f/%.1f", e.output == gvs::drivers::StrobeOutput::led ? "led" : "trig", e.on ? "+" : "-",
                    static_cast<double>(e.target_ns - start_ns) / 1e3,
                    static_cast<double>(e.achieved_ns - e.target_ns) / 1e3);
      }
      std::printf("\n");
    }
    for (const gvs::drivers::StrobeEdge& e : strobe.last_edges()) {
      const double late_us = static_cast<double>(e.achieved_ns - e.target_ns) / 1e3;
      if (e.achieved_ns < e.target_ns) ++early;
      if (e.output == gvs::drivers::StrobeOutput::trigger) {
        if (e.on) late_trigger.push_back(late_us);
        continue;
      }
      if (e.on) {
        late_led_on.push_back(late_us);
        if (pulse < gvs::core::ExposurePlan::kMaxPulses) on_ns[pulse] = e.achieved_ns;
        if (pulse == 1) {
          separation_err.push_back(std::fabs(static_cast<double>(on_ns[1] - on_ns[0]) / 1e3 - separation_us));
        }
      } else {
        late_led_off.push_back(late_us);
        const double nominal_us = plan.pulse_count ? pulse_us : plan.exposure_us;
        if (pulse < gvs::core::ExposurePlan::kMaxPulses) {
          duration_err.push_back(std::fabs(static_cast<double>(e.achieved_ns - on_ns[pulse]) / 1e3 - nominal_us));
        }
        ++pulse;
      }
    }
    // A frame that overran its period starts the next one from now.
    const std::int64_t now = now_ns();
    if (start_ns + period_ns < now) start_ns = now - period_ns + period_ns / 10;
  }

  std::printf("edge lateness (after the set-value call - due):\n");
  if (!late_trigger.empty()) print("trigger on", late_trigger);
  print("LED on", late_led_on);
  print("LED off", late_led_off);
  std::printf("what the estimate sees (|achieved - planned|):\n");
  print("pulse duration error", duration_err);
  const Stats d = stats_us(duration_err);
  const double nominal_us = plan.pulse_count ? pulse_us : plan.exposure_us;
  std::printf("  -> blur length error (single strobe) median %.1f %%, p99 %.1f %% of %.0f us\n",
              100.0 * d.median / nominal_us, 100.0 * d.p99 / nominal_us, nominal_us);
  if (!separation_err.empty()) {
    print("pulse separation error", separation_err);
    const Stats s = stats_us(separation_err);
    std::printf("  -> speed error (double pulse) median %.2f %%, p99 %.2f %% of %.0f us separation\n",
                100.0 * s.median / separation_us, 100.0 * s.p99 / separation_us, separation_us);
  }
  std::printf("edges %zu, late (> %.0f us) %zu, early %zu, set-value errors %zu\n", edges, c.late_limit_us,
              late_edges, early, errors);
  if (early > 0 || errors > 0) {
    std::printf("strobe-bench: FAIL (an edge came before its time or a set-value call failed)\n");
    return 1;
  }
  std::printf("strobe-bench: OK\n");
  return 0;
}
