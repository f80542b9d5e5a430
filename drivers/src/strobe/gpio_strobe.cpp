// GpioStrobe: libgpiod 1.6 (Debian 12). Lines are requested once, at
// set-up; a frame is a series of absolute-time sleeps and set-value calls.
#include "gvs/drivers/gpio_strobe.hpp"

#include <gpiod.h>

#include <cerrno>
#include <cstring>
#include <stdexcept>

#include "gvs/drivers/clock.hpp"

namespace gvs::drivers {

namespace {

gpiod_line* request_output(gpiod_chip* chip, const StrobeConfig& c, int offset, const char* role) {
  const std::string where = "GPIO chip '" + c.gpio_chip + "' line " + std::to_string(offset) + " (" + role + ")";
  gpiod_line* line = gpiod_chip_get_line(chip, static_cast<unsigned>(offset));
  if (line == nullptr) {
    throw std::runtime_error(where + ": no such line (" + std::strerror(errno) + "; the chip has " +
                             std::to_string(gpiod_chip_num_lines(chip)) +
                             " lines: fix [light] " + role + "_line, see gpioinfo)");
  }
  const int flags = c.active_low ? GPIOD_LINE_REQUEST_FLAG_ACTIVE_LOW : 0;
  if (gpiod_line_request_output_flags(line, c.consumer.c_str(), flags, 0) != 0) {
    const char* user = gpiod_line_consumer(line);
    throw std::runtime_error(where + ": cannot request it as an output (" + std::strerror(errno) + ")" +
                             (user != nullptr ? std::string("; it is used by '") + user + "'" : std::string()) +
                             ": free the line or choose another in [light]");
  }
  return line;
}

}  // namespace

GpioStrobe::GpioStrobe(const StrobeConfig& config)
    : config_(config),
      spin_ns_(static_cast<std::int64_t>(config.spin_us * 1000.0)),
      late_limit_ns_(static_cast<std::int64_t>(config.late_limit_us * 1000.0)),
      trigger_pulse_ns_(static_cast<std::int64_t>(config.trigger_pulse_us * 1000.0)) {
  if (config.led_line < 0) {
    throw std::runtime_error("[light] driver = \"gpio\" needs led_line (the LED ring's line on " + config.gpio_chip + ")");
  }
  if (config.led_line == config.trigger_line) {
    throw std::runtime_error("[light] led_line and trigger_line are both " + std::to_string(config.led_line) +
                             " on " + config.gpio_chip + ": give the trigger its own line or -1");
  }
  chip_ = gpiod_chip_open_lookup(config.gpio_chip.c_str());
  if (chip_ == nullptr) {
    throw std::runtime_error("GPIO chip '" + config.gpio_chip + "': cannot open it (" + std::strerror(errno) +
                             "); list the chips with gpiodetect and set [light] chip (name, number or /dev path), "
                             "and check gvsd may open /dev/gpiochip*");
  }
  try {
    led_ = request_output(chip_, config, config.led_line, "led");
    if (config.trigger_line >= 0) trigger_ = request_output(chip_, config, config.trigger_line, "trigger");
  } catch (...) {
    gpiod_chip_close(chip_);  // releases the lines requested so far
    throw;
  }
}

GpioStrobe::~GpioStrobe() {
  if (led_ != nullptr) gpiod_line_set_value(led_, 0);
  if (trigger_ != nullptr) gpiod_line_set_value(trigger_, 0);
  gpiod_chip_close(chip_);
}

std::string GpioStrobe::describe() const {
  std::string s = "gpio " + config_.gpio_chip + " led line " + std::to_string(config_.led_line);
  if (config_.trigger_line >= 0) s += ", trigger line " + std::to_string(config_.trigger_line);
  s += config_.active_low ? " (active low" : " (active high";
  return s + ", consumer " + config_.consumer + ")";
}

bool GpioStrobe::arm(const core::ExposurePlan& plan, double) noexcept {
  plan_ = plan;
  return true;
}

FireReport GpioStrobe::fire(std::int64_t start_ns) noexcept {
  schedule_ = make_edge_schedule(plan_, start_ns, trigger_ != nullptr, trigger_pulse_ns_);
  FireReport report;
  for (std::size_t i = 0; i < schedule_.count; ++i) {
    StrobeEdge& e = schedule_.edges[i];
    gpiod_line* line = e.output == StrobeOutput::led ? led_ : trigger_;
    // Sleep to shortly before the edge, then spin: the wake-up's jitter
    // lands in the spin instead of on the line.
    if (e.target_ns - spin_ns_ > mono_now_ns()) {
      sleep_until_ns(e.target_ns - spin_ns_);
      if (config_.warm_up_write) {
        // Each line gets its present level again: no edge, but the path is warm.
        if (gpiod_line_set_value(led_, led_on_ ? 1 : 0) != 0) report.error = true;
        if (trigger_ != nullptr && gpiod_line_set_value(trigger_, trigger_on_ ? 1 : 0) != 0) report.error = true;
      }
    }
    while (mono_now_ns() < e.target_ns) {
    }
    if (gpiod_line_set_value(line, e.on ? 1 : 0) != 0) report.error = true;
    e.achieved_ns = mono_now_ns();
    (e.output == StrobeOutput::led ? led_on_ : trigger_on_) = e.on;
    const std::int64_t late_ns = e.achieved_ns - e.target_ns;
    if (late_ns > late_limit_ns_) ++report.late_edges;
    if (late_ns > report.max_late_ns) report.max_late_ns = late_ns;
    ++report.edges;
  }
  return report;
}

}  // namespace gvs::drivers
