// PwmStrobe: the Linux PWM sysfs interface. Each value is written as the
// shell's `echo N > file` does (open with O_TRUNC, write, close), which works
// on sysfs and on the plain files of a test's fake tree alike.
#include "gvs/drivers/pwm_strobe.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <stdexcept>
#include <thread>

namespace gvs::drivers {

namespace {

/// Writes `text` into `path`; errno is kept on failure.
bool write_text(const char* path, const char* text, std::size_t length) noexcept {
  const int fd = ::open(path, O_WRONLY | O_TRUNC | O_CLOEXEC);
  if (fd < 0) return false;
  const ssize_t written = ::write(fd, text, length);
  const int saved = errno;
  ::close(fd);
  errno = saved;
  return written == static_cast<ssize_t>(length);
}

bool write_number(const std::string& path, std::int64_t value) noexcept {
  char text[32];
  const int n = std::snprintf(text, sizeof text, "%lld\n", static_cast<long long>(value));
  return n > 0 && write_text(path.c_str(), text, static_cast<std::size_t>(n));
}

void write_or_throw(const std::string& path, const std::string& text, const char* what) {
  if (!write_text(path.c_str(), text.data(), text.size())) {
    throw std::runtime_error("PWM: cannot write '" + text.substr(0, text.find('\n')) + "' to " + path + " (" +
                             std::strerror(errno) + "): " + what);
  }
}

}  // namespace

PwmStrobe::PwmStrobe(const StrobeConfig& c) {
  namespace fs = std::filesystem;
  const fs::path chip_dir = fs::path(c.pwm_sysfs_root) / ("pwmchip" + std::to_string(c.pwm_chip));
  std::error_code ec;
  if (!fs::is_directory(chip_dir, ec)) {
    throw std::runtime_error("PWM chip " + chip_dir.string() +
                             " not found: enable the PWM peripheral (device-tree overlay) and set [light] pwm_chip "
                             "to one of the pwmchipN under " + c.pwm_sysfs_root);
  }
  const fs::path channel_dir = chip_dir / ("pwm" + std::to_string(c.pwm_channel));
  if (!fs::is_directory(channel_dir, ec)) {
    write_or_throw((chip_dir / "export").string(), std::to_string(c.pwm_channel) + "\n",
                   "check [light] pwm_channel against the chip's npwm and that gvsd may write the PWM sysfs files");
    // The kernel creates pwmM at once; udev may take a moment to fix its permissions.
    for (int i = 0; i < 100 && !fs::is_directory(channel_dir, ec); ++i) {
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    if (!fs::is_directory(channel_dir, ec)) {
      throw std::runtime_error("PWM: " + channel_dir.string() + " did not appear after writing " +
                               std::to_string(c.pwm_channel) + " to " + (chip_dir / "export").string() +
                               ": check [light] pwm_channel");
    }
  }
  channel_dir_ = channel_dir.string();
  period_path_ = (channel_dir / "period").string();
  duty_path_ = (channel_dir / "duty_cycle").string();
  enable_path_ = (channel_dir / "enable").string();
  write_or_throw(enable_path_, "0\n", "check that gvsd may write the PWM sysfs files (udev rule or group)");
  write_or_throw((channel_dir / "polarity").string(), c.active_low ? "inversed\n" : "normal\n",
                 "this PWM cannot invert: wire the LED driver active high and set [light] active_low = false");
}

PwmStrobe::~PwmStrobe() {
  if (enabled_) write_text(enable_path_.c_str(), "0\n", 2);
}

std::string PwmStrobe::describe() const { return "pwm " + channel_dir_; }

bool PwmStrobe::arm(const core::ExposurePlan& plan, double frame_period_us) noexcept {
  if (plan.pulse_count > 1 || frame_period_us <= 0.0) return false;
  const double lit_us = plan.pulse_count == 0 ? plan.exposure_us : plan.pulses[0].duration_us;
  const auto period_ns = static_cast<std::int64_t>(frame_period_us * 1000.0 + 0.5);
  const auto duty_ns = static_cast<std::int64_t>(lit_us * 1000.0 + 0.5);
  if (duty_ns <= 0 || duty_ns > period_ns) return false;
  if (period_ns == period_ns_ && duty_ns == duty_ns_ && enabled_) return true;
  // The kernel refuses duty_cycle > period at every step: shrink duty first
  // when the new period is shorter than the duty now set.
  bool ok = true;
  if (period_ns < duty_ns_) {
    ok = write_number(duty_path_, duty_ns) && write_number(period_path_, period_ns);
  } else {
    ok = write_number(period_path_, period_ns) && write_number(duty_path_, duty_ns);
  }
  if (!ok) return false;
  period_ns_ = period_ns;
  duty_ns_ = duty_ns;
  if (!enabled_) {
    if (!write_text(enable_path_.c_str(), "1\n", 2)) return false;
    enabled_ = true;
  }
  return true;
}

}  // namespace gvs::drivers
