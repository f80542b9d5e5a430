// [light] in gvsd.toml: defaults, the values it takes, and the refusals that
// name the key.
#include <gtest/gtest.h>

#include "gvs/daemon/config.hpp"

using gvs::daemon::ConfigError;
using gvs::daemon::parse_config;

namespace {

/// The message of the ConfigError that `toml` raises ("" when none).
std::string refusal(const std::string& toml) {
  try {
    (void)parse_config(toml, "test.toml");
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST(LightConfig, DefaultIsNoLight) {
  const auto c = parse_config("", "test.toml");
  EXPECT_EQ(c.light.driver, "none");
  EXPECT_EQ(c.light.trigger_line, -1);
  EXPECT_FALSE(c.light.active_low);
}

TEST(LightConfig, GpioKeysAreRead) {
  const auto c = parse_config(R"([light]
driver = "gpio"
chip = "/dev/gpiochip2"
led_line = 17
trigger_line = 27
active_low = true
consumer = "gvsd-car"
trigger_pulse_us = 20.0
spin_us = 80
late_limit_us = 150.0
)",
                              "test.toml");
  EXPECT_EQ(c.light.driver, "gpio");
  EXPECT_EQ(c.light.gpio_chip, "/dev/gpiochip2");
  EXPECT_EQ(c.light.led_line, 17);
  EXPECT_EQ(c.light.trigger_line, 27);
  EXPECT_TRUE(c.light.active_low);
  EXPECT_EQ(c.light.consumer, "gvsd-car");
  EXPECT_DOUBLE_EQ(c.light.trigger_pulse_us, 20.0);
  EXPECT_DOUBLE_EQ(c.light.spin_us, 80.0);
  EXPECT_DOUBLE_EQ(c.light.late_limit_us, 150.0);
}

TEST(LightConfig, PwmKeysAreRead) {
  const auto c = parse_config("[light]\ndriver = \"pwm\"\npwm_sysfs_root = \"/tmp/pwm\"\npwm_chip = 2\npwm_channel = 1\n",
                              "test.toml");
  EXPECT_EQ(c.light.driver, "pwm");
  EXPECT_EQ(c.light.pwm_sysfs_root, "/tmp/pwm");
  EXPECT_EQ(c.light.pwm_chip, 2);
  EXPECT_EQ(c.light.pwm_channel, 1);
}

TEST(LightConfig, InvalidValuesAreRefusedNamingTheKey) {
  const std::pair<const char*, const char*> cases[] = {
      {"[light]\ndriver = \"laser\"\n", "[light] driver"},
      {"[light]\nled_line = -2\n", "[light] led_line"},
      {"[light]\nled_line = \"17\"\n", "[light] led_line"},
      {"[light]\ntrigger_line = -5\n", "[light] trigger_line"},
      {"[light]\nactive_low = 1\n", "[light] active_low"},
      {"[light]\nconsumer = \"\"\n", "[light] consumer"},
      {"[light]\nspin_us = 5000\n", "[light] spin_us"},
      {"[light]\npwm_channel = -1\n", "[light] pwm_channel"},
      {"[light]\nled = 3\n", "unknown key 'led' in [light]"},
      {"[light]\ndriver = \"gpio\"\n", "needs led_line"},
      {"[light]\ndriver = \"gpio\"\nled_line = 4\ntrigger_line = 4\n", "both 4"},
  };
  for (const auto& [toml, want] : cases) {
    const std::string msg = refusal(toml);
    EXPECT_NE(msg.find(want), std::string::npos) << toml << " -> '" << msg << "'";
    EXPECT_NE(msg.find("test.toml"), std::string::npos) << msg;
  }
}

TEST(LightConfig, ChangingTheLightNeedsARestart) {
  const auto a = parse_config("", "a.toml");
  const auto b = parse_config("[light]\ndriver = \"gpio\"\nled_line = 1\n", "b.toml");
  const auto changed = gvs::daemon::restart_only_changes(a, b);
  ASSERT_EQ(changed.size(), 2u);
  EXPECT_EQ(changed[0], "light.driver");
  EXPECT_EQ(changed[1], "light.led_line");
}
