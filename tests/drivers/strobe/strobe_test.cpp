// The strobe drivers' hardware-free parts: the edge schedule of a plan and
// the PWM driver against a fake sysfs tree in a temporary folder.
#include <gtest/gtest.h>

#include <array>
#include <span>
#include <vector>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <unistd.h>

#include "gvs/drivers/gpio_strobe.hpp"
#include "gvs/drivers/pwm_strobe.hpp"

namespace fs = std::filesystem;
using gvs::drivers::EdgeSchedule;
using gvs::drivers::StrobeOutput;
using gvs::drivers::LitInterval;
using gvs::drivers::StrobeEdge;
using gvs::drivers::led_intervals;
using gvs::drivers::light_in_exposure;
namespace core = gvs::core;

namespace {

gvs::core::ExposurePlan double_pulse(double first_us, double second_us, double duration_us) {
  gvs::core::ExposurePlan p;
  p.exposure_us = second_us + duration_us;
  p.pulses[0] = {first_us, duration_us};
  p.pulses[1] = {second_us, duration_us};
  p.pulse_count = 2;
  return p;
}

}  // namespace

TEST(EdgeSchedule, ContinuousExposureIsOneLedPulseAfterTheTrigger) {
  gvs::core::ExposurePlan plan;
  plan.exposure_us = 3000.0;
  const EdgeSchedule s = gvs::drivers::make_edge_schedule(plan, 1'000'000, true, 10'000);
  ASSERT_EQ(s.count, 4u);
  EXPECT_EQ(s.edges[0].output, StrobeOutput::trigger);  // same time as the LED: the trigger first
  EXPECT_TRUE(s.edges[0].on);
  EXPECT_EQ(s.edges[0].target_ns, 1'000'000);
  EXPECT_EQ(s.edges[1].output, StrobeOutput::led);
  EXPECT_TRUE(s.edges[1].on);
  EXPECT_EQ(s.edges[2].output, StrobeOutput::trigger);
  EXPECT_FALSE(s.edges[2].on);
  EXPECT_EQ(s.edges[2].target_ns, 1'010'000);
  EXPECT_EQ(s.edges[3].output, StrobeOutput::led);
  EXPECT_FALSE(s.edges[3].on);
  EXPECT_EQ(s.edges[3].target_ns, 4'000'000);
}

TEST(EdgeSchedule, DoublePulseWithoutTriggerInTimeOrder) {
  const auto plan = double_pulse(1000.0, 100.0, 20.0);  // given out of order
  const EdgeSchedule s = gvs::drivers::make_edge_schedule(plan, 0, false, 10'000);
  ASSERT_EQ(s.count, 4u);
  const std::int64_t want[] = {100'000, 120'000, 1'000'000, 1'020'000};
  for (std::size_t i = 0; i < 4; ++i) {
    EXPECT_EQ(s.edges[i].output, StrobeOutput::led);
    EXPECT_EQ(s.edges[i].on, i % 2 == 0) << i;
    EXPECT_EQ(s.edges[i].target_ns, want[i]) << i;
  }
}

TEST(EdgeSchedule, OverlappingPulsesMergeSoTheLedNeverSwitchesOnTwice) {
  auto plan = double_pulse(0.0, 15.0, 20.0);
  const EdgeSchedule s = gvs::drivers::make_edge_schedule(plan, 0, false, 0);
  ASSERT_EQ(s.count, 2u);
  EXPECT_EQ(s.edges[0].target_ns, 0);
  EXPECT_EQ(s.edges[1].target_ns, 35'000);
  plan.pulses[1].duration_us = 0.0;  // an empty pulse drives nothing
  EXPECT_EQ(gvs::drivers::make_edge_schedule(plan, 0, false, 0).count, 2u);
}

TEST(EdgeSchedule, EightPulsesAndATriggerFit) {
  gvs::core::ExposurePlan plan;
  plan.pulse_count = gvs::core::ExposurePlan::kMaxPulses;
  for (std::size_t i = 0; i < plan.pulse_count; ++i) plan.pulses[i] = {100.0 * static_cast<double>(i), 10.0};
  const EdgeSchedule s = gvs::drivers::make_edge_schedule(plan, 0, true, 5'000);
  EXPECT_EQ(s.count, EdgeSchedule::kMaxEdges);
  for (std::size_t i = 1; i < s.count; ++i) EXPECT_LE(s.edges[i - 1].target_ns, s.edges[i].target_ns);
}

// --- PWM sysfs against a fake tree -------------------------------------------------

class PwmFakeSysfs : public ::testing::Test {
 protected:
  void SetUp() override {
    root_ = fs::temp_directory_path() / ("gvs-pwm-" + std::to_string(::getpid()) + "-" +
                                         ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(root_);
    fs::create_directories(root_ / "pwmchip1");
    std::ofstream(root_ / "pwmchip1" / "export").put('\n');
  }
  void TearDown() override { fs::remove_all(root_); }

  /// What the kernel creates when a channel is exported.
  void make_channel(int channel) {
    const fs::path d = root_ / "pwmchip1" / ("pwm" + std::to_string(channel));
    fs::create_directories(d);
    for (const char* f : {"period", "duty_cycle", "enable", "polarity"}) std::ofstream(d / f) << "0\n";
  }
  std::string read(const std::string& rel) const {
    std::ifstream in(root_ / rel);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
  }
  gvs::drivers::StrobeConfig config(int channel) const {
    gvs::drivers::StrobeConfig c;
    c.driver = "pwm";
    c.pwm_sysfs_root = root_.string();
    c.pwm_chip = 1;
    c.pwm_channel = channel;
    return c;
  }

  fs::path root_;
};

TEST_F(PwmFakeSysfs, SinglePulseSetsPeriodDutyAndEnables) {
  make_channel(0);
  auto c = config(0);
  c.active_low = true;
  gvs::drivers::PwmStrobe pwm(c);
  EXPECT_EQ(read("pwmchip1/pwm0/polarity"), "inversed\n");
  EXPECT_EQ(read("pwmchip1/pwm0/enable"), "0\n");
  gvs::core::ExposurePlan plan;
  plan.pulse_count = 1;
  plan.pulses[0] = {0.0, 120.0};
  ASSERT_TRUE(pwm.arm(plan, 1e6 / 60.0));
  EXPECT_EQ(read("pwmchip1/pwm0/period"), "16666667\n");
  EXPECT_EQ(read("pwmchip1/pwm0/duty_cycle"), "120000\n");
  EXPECT_EQ(read("pwmchip1/pwm0/enable"), "1\n");
  EXPECT_TRUE(pwm.hardware_timed());
  EXPECT_TRUE(pwm.last_edges().empty());
}

TEST_F(PwmFakeSysfs, ContinuousExposureIsTheDutyAndShorterValuesReplaceLongerOnes) {
  make_channel(2);
  gvs::drivers::PwmStrobe pwm(config(2));
  EXPECT_EQ(read("pwmchip1/pwm2/polarity"), "normal\n");
  gvs::core::ExposurePlan plan;
  plan.exposure_us = 3000.0;
  ASSERT_TRUE(pwm.arm(plan, 10'000.0));
  EXPECT_EQ(read("pwmchip1/pwm2/duty_cycle"), "3000000\n");
  plan.exposure_us = 50.0;
  ASSERT_TRUE(pwm.arm(plan, 5'000.0));
  EXPECT_EQ(read("pwmchip1/pwm2/period"), "5000000\n");
  EXPECT_EQ(read("pwmchip1/pwm2/duty_cycle"), "50000\n");  // no stale digits left behind
  EXPECT_EQ(pwm.period_ns(), 5'000'000);
  EXPECT_EQ(pwm.duty_ns(), 50'000);
}

TEST_F(PwmFakeSysfs, RefusesDoublePulseAndDutyLongerThanThePeriod) {
  make_channel(0);
  gvs::drivers::PwmStrobe pwm(config(0));
  EXPECT_FALSE(pwm.arm(double_pulse(0.0, 500.0, 20.0), 16'666.0));
  gvs::core::ExposurePlan plan;
  plan.exposure_us = 20'000.0;
  EXPECT_FALSE(pwm.arm(plan, 16'666.0));
  EXPECT_EQ(read("pwmchip1/pwm0/enable"), "0\n");  // nothing was enabled
}

TEST_F(PwmFakeSysfs, DisablesOnDestruction) {
  make_channel(0);
  {
    gvs::drivers::PwmStrobe pwm(config(0));
    gvs::core::ExposurePlan plan;
    ASSERT_TRUE(pwm.arm(plan, 16'666.0));
    EXPECT_EQ(read("pwmchip1/pwm0/enable"), "1\n");
  }
  EXPECT_EQ(read("pwmchip1/pwm0/enable"), "0\n");
}

TEST_F(PwmFakeSysfs, ExportsAMissingChannelAndNamesThePathWhenItDoesNotAppear) {
  // The fake kernel does not create pwm3 on export: the error names the folder.
  try {
    gvs::drivers::PwmStrobe pwm(config(3));
    FAIL() << "expected an error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find((root_ / "pwmchip1" / "pwm3").string()), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("pwm_channel"), std::string::npos) << e.what();
  }
  EXPECT_EQ(read("pwmchip1/export"), "3\n");
}

TEST_F(PwmFakeSysfs, MissingChipNamesThePathAndTheKey) {
  auto c = config(0);
  c.pwm_chip = 7;
  try {
    gvs::drivers::PwmStrobe pwm(c);
    FAIL() << "expected an error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find((root_ / "pwmchip7").string()), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("pwm_chip"), std::string::npos) << e.what();
  }
}

// --- set-up errors of the GPIO driver (no chip needed) ------------------------------

// The light a real camera's frame got: the LED's measured on-times inside
// the shutter time the camera reported.
TEST(LightInExposure, MeasuredPulsesInsideTheShutterBecomeTheFramesPulses) {
  // A double pulse as fired: trigger, LED 20 us at +100 us and 20 us at +600 us.
  const std::vector<StrobeEdge> edges{{StrobeOutput::trigger, true, 0, 1'000'000},
                                      {StrobeOutput::trigger, false, 0, 1'010'000},
                                      {StrobeOutput::led, true, 0, 1'100'000},
                                      {StrobeOutput::led, false, 0, 1'120'000},
                                      {StrobeOutput::led, true, 0, 1'600'000},
                                      {StrobeOutput::led, false, 0, 1'620'500}};
  std::array<LitInterval, 4> lit{};
  ASSERT_EQ(led_intervals(edges, lit), 2u);
  EXPECT_EQ(lit[1].on_ns, 1'600'000);
  EXPECT_EQ(lit[1].off_ns, 1'620'500);

  // Shutter open 1 ms from 1.05 ms: both pulses inside, at their measured offsets.
  core::ExposurePlan plan;
  ASSERT_TRUE(light_in_exposure(std::span(lit.data(), 2), 1'050'000, 1000.0, plan));
  ASSERT_EQ(plan.pulse_count, 2u);
  EXPECT_DOUBLE_EQ(plan.exposure_us, 1000.0);
  EXPECT_DOUBLE_EQ(plan.pulses[0].start_us, 50.0);
  EXPECT_DOUBLE_EQ(plan.pulses[0].duration_us, 20.0);
  EXPECT_DOUBLE_EQ(plan.pulses[1].start_us, 550.0);
  EXPECT_DOUBLE_EQ(plan.pulses[1].duration_us, 20.5);

  // Shutter closed before the second pulse ended: only what fell inside counts.
  ASSERT_TRUE(light_in_exposure(std::span(lit.data(), 2), 1'050'000, 560.0, plan));
  ASSERT_EQ(plan.pulse_count, 2u);
  EXPECT_DOUBLE_EQ(plan.pulses[1].duration_us, 10.0);

  // Shutter open between the pulses: no light, the frame must not be measured.
  EXPECT_FALSE(light_in_exposure(std::span(lit.data(), 2), 1'200'000, 300.0, plan));
  // LED on all through the shutter: a continuous exposure (no pulses).
  const std::array<LitInterval, 1> on{{{900'000, 5'000'000}}};
  ASSERT_TRUE(light_in_exposure(on, 1'000'000, 3000.0, plan));
  EXPECT_EQ(plan.pulse_count, 0u);
  EXPECT_DOUBLE_EQ(plan.exposure_us, 3000.0);
}

TEST(GpioStrobeSetup, MissingChipNamesItAndSaysWhatToDo) {
  gvs::drivers::StrobeConfig c;
  c.driver = "gpio";
  c.gpio_chip = "/nonexistent/gpiochip9";
  c.led_line = 1;
  try {
    gvs::drivers::GpioStrobe g(c);
    FAIL() << "expected an error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent/gpiochip9"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("gpiodetect"), std::string::npos) << e.what();
  }
}

TEST(GpioStrobeSetup, NeedsAnLedLineDistinctFromTheTrigger) {
  gvs::drivers::StrobeConfig c;
  c.driver = "gpio";
  EXPECT_THROW(gvs::drivers::GpioStrobe{c}, std::runtime_error);
  c.led_line = 2;
  c.trigger_line = 2;
  EXPECT_THROW(gvs::drivers::GpioStrobe{c}, std::runtime_error);
}

TEST(StrobeFactory, NoneIsNoDriverAndUnknownIsRefused) {
  gvs::drivers::StrobeConfig c;
  EXPECT_EQ(gvs::drivers::make_strobe_driver(c), nullptr);
  c.driver = "laser";
  EXPECT_THROW(gvs::drivers::make_strobe_driver(c), std::runtime_error);
}
