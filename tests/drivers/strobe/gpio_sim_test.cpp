// The GPIO strobe driver on a gpio-sim chip (run by ctest inside qemu:
// tests/bench/qemu-vcan.sh --gpio-sim 4 exports GVS_GPIO_SIM_CHIP and
// GVS_GPIO_SIM_SYSFS). The line levels are read back from gpio-sim's own
// sysfs attributes (sim_gpioN/value: what the chip's output is driven to),
// independently of libgpiod. Without the chip every test fails.
#include <gpiod.h>
#include <gtest/gtest.h>
#include <time.h>

#include <cstdlib>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

#include "gvs/drivers/gpio_strobe.hpp"

namespace {

constexpr int kTriggerLine = 0;
constexpr int kLedLine = 1;

std::int64_t now_ns() {
  timespec ts{};
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return static_cast<std::int64_t>(ts.tv_sec) * 1'000'000'000 + ts.tv_nsec;
}

class GpioSim : public ::testing::Test {
 protected:
  void SetUp() override {
    const char* chip = std::getenv("GVS_GPIO_SIM_CHIP");
    const char* sysfs = std::getenv("GVS_GPIO_SIM_SYSFS");
    ASSERT_TRUE(chip != nullptr && sysfs != nullptr)
        << "no simulated GPIO chip: run inside tests/bench/qemu-vcan.sh --gpio-sim 4 (ctest -R gpio does)";
    chip_ = chip;
    sysfs_ = sysfs;
  }
  /// The simulated line's level as gpio-sim holds it (physical, not logical).
  int level(int line) const {
    std::ifstream in(sysfs_ + "/sim_gpio" + std::to_string(line) + "/value");
    int v = -1;
    in >> v;
    return v;
  }
  gvs::drivers::StrobeConfig config(bool active_low) const {
    gvs::drivers::StrobeConfig c;
    c.driver = "gpio";
    c.gpio_chip = chip_;
    c.led_line = kLedLine;
    c.trigger_line = kTriggerLine;
    c.active_low = active_low;
    c.consumer = "gvs-strobe-test";
    return c;
  }
  /// Fires `plan` once and samples both lines at `at_ms` after its start.
  std::vector<std::pair<int, int>> fire_and_sample(gvs::drivers::GpioStrobe& strobe,
                                                   const gvs::dsp::ExposurePlan& plan,
                                                   const std::vector<double>& at_ms) {
    strobe.arm(plan, 1e6);
    const std::int64_t start_ns = now_ns() + 50'000'000;
    std::vector<std::pair<int, int>> seen(at_ms.size());
    std::thread sampler([&] {
      for (std::size_t i = 0; i < at_ms.size(); ++i) {
        const std::int64_t t = start_ns + static_cast<std::int64_t>(at_ms[i] * 1e6);
        timespec ts{static_cast<time_t>(t / 1'000'000'000), static_cast<long>(t % 1'000'000'000)};
        clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, nullptr);
        seen[i] = {level(kTriggerLine), level(kLedLine)};
      }
    });
    const gvs::drivers::FireReport r = strobe.fire(start_ns);
    sampler.join();
    EXPECT_FALSE(r.error);
    return seen;
  }

  std::string chip_, sysfs_;
};

/// Slow enough to sample under qemu TCG: a 100 ms trigger, pulses of 150 ms.
gvs::dsp::ExposurePlan slow_double_pulse() {
  gvs::dsp::ExposurePlan p;
  p.pulse_count = 2;
  p.pulses[0] = {0.0, 150'000.0};
  p.pulses[1] = {300'000.0, 150'000.0};
  p.exposure_us = 450'000.0;
  return p;
}

}  // namespace

TEST_F(GpioSim, RequestsBothLinesOffWithTheConsumerNameAndReleasesThem) {
  {
    gvs::drivers::GpioStrobe strobe(config(false));
    EXPECT_EQ(level(kTriggerLine), 0);
    EXPECT_EQ(level(kLedLine), 0);
    gpiod_chip* chip = gpiod_chip_open_lookup(chip_.c_str());
    ASSERT_NE(chip, nullptr);
    gpiod_line* led = gpiod_chip_get_line(chip, kLedLine);
    ASSERT_NE(led, nullptr);
    EXPECT_TRUE(gpiod_line_is_used(led));
    EXPECT_EQ(gpiod_line_direction(led), GPIOD_LINE_DIRECTION_OUTPUT);
    ASSERT_NE(gpiod_line_consumer(led), nullptr);
    EXPECT_STREQ(gpiod_line_consumer(led), "gvs-strobe-test");
    // A second user of the same line is refused with the line named.
    try {
      gvs::drivers::GpioStrobe second(config(false));
      ADD_FAILURE() << "the LED line was requested twice";
    } catch (const std::runtime_error& e) {
      EXPECT_NE(std::string(e.what()).find("line 1"), std::string::npos) << e.what();
    }
    gpiod_chip_close(chip);
  }
  gpiod_chip* chip = gpiod_chip_open_lookup(chip_.c_str());
  ASSERT_NE(chip, nullptr);
  EXPECT_FALSE(gpiod_line_is_used(gpiod_chip_get_line(chip, kLedLine)));
  gpiod_chip_close(chip);
}

TEST_F(GpioSim, DoublePulseDrivesTheLinesAtThePlannedTimes) {
  auto c = config(false);
  c.trigger_pulse_us = 100'000.0;
  gvs::drivers::GpioStrobe strobe(c);
  // trigger on 0-100 ms; LED on 0-150 and 300-450 ms
  const auto seen = fire_and_sample(strobe, slow_double_pulse(), {50.0, 125.0, 225.0, 375.0, 550.0});
  const std::pair<int, int> want[] = {{1, 1}, {0, 1}, {0, 0}, {0, 1}, {0, 0}};
  for (std::size_t i = 0; i < seen.size(); ++i) EXPECT_EQ(seen[i], want[i]) << "sample " << i;
  ASSERT_EQ(strobe.last_edges().size(), 6u);
  for (const auto& e : strobe.last_edges()) {
    EXPECT_GE(e.achieved_ns, e.target_ns);              // never early
    EXPECT_LT(e.achieved_ns - e.target_ns, 20'000'000); // generous: emulated guest
  }
}

TEST_F(GpioSim, SinglePulseActiveLowInvertsTheLines) {
  auto c = config(true);
  c.trigger_pulse_us = 100'000.0;
  gvs::drivers::GpioStrobe strobe(c);
  EXPECT_EQ(level(kTriggerLine), 1);  // off = high
  EXPECT_EQ(level(kLedLine), 1);
  gvs::dsp::ExposurePlan p;
  p.pulse_count = 1;
  p.pulses[0] = {200'000.0, 150'000.0};
  p.exposure_us = 350'000.0;
  const auto seen = fire_and_sample(strobe, p, {50.0, 150.0, 275.0, 450.0});
  const std::pair<int, int> want[] = {{0, 1}, {1, 1}, {1, 0}, {1, 1}};
  for (std::size_t i = 0; i < seen.size(); ++i) EXPECT_EQ(seen[i], want[i]) << "sample " << i;
}

TEST_F(GpioSim, ContinuousExposureKeepsTheLedOnForTheExposure) {
  gvs::drivers::GpioStrobe strobe(config(false));
  gvs::dsp::ExposurePlan p;  // no pulses
  p.exposure_us = 200'000.0;
  const auto seen = fire_and_sample(strobe, p, {100.0, 300.0});
  EXPECT_EQ(seen[0].second, 1);
  EXPECT_EQ(seen[1].second, 0);
  EXPECT_EQ(seen[1].first, 0);  // the 10 us trigger is long over
}

TEST_F(GpioSim, FastDoublePulseTimingIsRecordedAndPrinted) {
  gvs::drivers::GpioStrobe strobe(config(false));
  gvs::dsp::ExposurePlan p;
  p.pulse_count = 2;
  p.pulses[0] = {0.0, 20.0};
  p.pulses[1] = {500.0, 20.0};
  p.exposure_us = 520.0;
  strobe.arm(p, 16'667.0);
  std::int64_t worst_ns = 0;
  double worst_separation_error_us = 0.0;
  for (int frame = 0; frame < 50; ++frame) {
    const auto r = strobe.fire(now_ns() + 2'000'000);
    EXPECT_FALSE(r.error);
    const auto edges = strobe.last_edges();
    ASSERT_EQ(edges.size(), 6u);  // trigger on/off, two LED pulses
    std::int64_t on_ns[2]{};
    int pulse = 0;
    for (const auto& e : edges) {
      EXPECT_GE(e.achieved_ns, e.target_ns);
      worst_ns = std::max(worst_ns, e.achieved_ns - e.target_ns);
      if (e.output == gvs::drivers::StrobeOutput::led && e.on) on_ns[pulse++] = e.achieved_ns;
    }
    worst_separation_error_us =
        std::max(worst_separation_error_us, std::abs(static_cast<double>(on_ns[1] - on_ns[0]) / 1e3 - 500.0));
  }
  std::printf("gpio-sim: 50 double pulses, worst edge lateness %.1f us, worst separation error %.1f us\n",
              static_cast<double>(worst_ns) / 1e3, worst_separation_error_us);
  EXPECT_LT(worst_ns, 50'000'000);  // only a sanity bound: the guest is emulated (figures: gvs_strobe_bench)
  EXPECT_EQ(level(kLedLine), 0);
}
