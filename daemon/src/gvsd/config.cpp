// Reads gvsd's TOML configuration with strict checking: every key must be
// known, of the right type and inside its range, or start-up stops with a
// message naming the key and what is allowed.
#include "gvs/daemon/config.hpp"

#include <algorithm>
#include <fstream>
#include <set>
#include <sstream>
#include <stdexcept>

#include <toml++/toml.h>

#include "gvs/drivers/sim/ground_spec.hpp"

namespace gvs::daemon {

namespace {

std::string where(const std::string& origin, const toml::node& node) {
  std::ostringstream s;
  s << origin;
  if (node.source().begin.line > 0) s << ':' << node.source().begin.line;
  return s.str();
}

std::string fmt_num(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

/// One [section] of the file: reads the keys it knows, then complains about
/// the ones nobody read.
class Section {
 public:
  Section(const toml::table* table, std::string name, const std::string& origin)
      : table_(table), name_(std::move(name)), origin_(origin) {}

  void real(std::string_view key, double& out, double lo, double hi, std::string_view unit) {
    const toml::node* n = find(key);
    if (n == nullptr) return;
    double v = 0.0;
    if (const auto* i = n->as_integer()) {
      v = static_cast<double>(i->get());
    } else if (const auto* f = n->as_floating_point()) {
      v = f->get();
    } else {
      fail(*n, key, "must be a number", range(lo, hi, unit));
    }
    if (!(v >= lo && v <= hi)) fail(*n, key, "= " + fmt_num(v) + " is out of range", range(lo, hi, unit));
    out = v;
  }

  template <typename Int>
  void integer(std::string_view key, Int& out, std::int64_t lo, std::int64_t hi, std::string_view unit) {
    const toml::node* n = find(key);
    if (n == nullptr) return;
    const auto* i = n->as_integer();
    if (i == nullptr) fail(*n, key, "must be an integer", range_i(lo, hi, unit));
    const std::int64_t v = i->get();
    if (v < lo || v > hi) fail(*n, key, "= " + std::to_string(v) + " is out of range", range_i(lo, hi, unit));
    out = static_cast<Int>(v);
  }

  void boolean(std::string_view key, bool& out) {
    const toml::node* n = find(key);
    if (n == nullptr) return;
    const auto* b = n->as_boolean();
    if (b == nullptr) fail(*n, key, "must be true or false", "");
    out = b->get();
  }

  /// A string; `allowed` empty = any non-empty text.
  void text(std::string_view key, std::string& out, const std::vector<std::string>& allowed = {}) {
    const toml::node* n = find(key);
    if (n == nullptr) return;
    const auto* s = n->as_string();
    std::string choices;
    for (const auto& a : allowed) {
      if (!choices.empty()) choices.append(", ");
      choices.append(a);
    }
    if (s == nullptr) fail(*n, key, "must be a string", choices.empty() ? "" : "one of: " + choices);
    const std::string& v = s->get();
    if (v.empty()) fail(*n, key, "must not be empty", "");
    if (!allowed.empty() && std::find(allowed.begin(), allowed.end(), v) == allowed.end()) {
      fail(*n, key, "= \"" + v + "\" is not allowed", "one of: " + choices);
    }
    out = v;
  }

  /// A sub-table (e.g. [threads.capture]); nullptr when absent.
  const toml::table* table(std::string_view key) {
    const toml::node* n = find(key);
    if (n == nullptr) return nullptr;
    const auto* t = n->as_table();
    if (t == nullptr) fail(*n, key, "must be a table", "");
    return t;
  }

  /// Throws for every key of the section that was not read.
  void finish() const {
    if (table_ == nullptr) return;
    for (auto&& [k, v] : *table_) {
      if (known_.count(std::string(k.str())) == 0) {
        std::string keys;
        for (const auto& kk : known_) {
          if (!keys.empty()) keys.append(", ");
          keys.append(kk);
        }
        throw ConfigError(where(origin_, v) + ": unknown key '" + std::string(k.str()) + "' in [" +
                          name_ + "]; known keys: " + keys);
      }
    }
  }

 private:
  const toml::node* find(std::string_view key) {
    known_.insert(std::string(key));
    if (table_ == nullptr) return nullptr;
    return table_->get(key);
  }

  static std::string range(double lo, double hi, std::string_view unit) {
    std::ostringstream s;
    s << "allowed " << lo << " .. " << hi;
    if (!unit.empty()) s << ' ' << unit;
    return s.str();
  }
  static std::string range_i(std::int64_t lo, std::int64_t hi, std::string_view unit) {
    std::ostringstream s;
    s << "allowed integers " << lo << " .. " << hi;
    if (!unit.empty()) s << ' ' << unit;
    return s.str();
  }

  [[noreturn]] void fail(const toml::node& n, std::string_view key, const std::string& what,
                         const std::string& allowed) const {
    std::string msg = where(origin_, n) + ": [" + name_ + "] " + std::string(key) + " " + what;
    if (!allowed.empty()) msg += " (" + allowed + ")";
    throw ConfigError(msg);
  }

  const toml::table* table_;
  std::string name_;
  const std::string& origin_;
  std::set<std::string> known_;
};

void read_thread(Section& threads, std::string_view name, ThreadConfig& out, const std::string& origin) {
  Section t(threads.table(name), "threads." + std::string(name), origin);
  t.integer("priority", out.priority, 0, 99, "(0 = normal scheduling, 1..99 = SCHED_FIFO)");
  t.integer("cpu", out.cpu, -1, 1023, "(-1 = any CPU)");
  t.finish();
}

// [light]: the LED ring and the camera trigger (drivers/strobe.hpp).
void read_light(Section& top, drivers::StrobeConfig& l, const std::string& origin) {
  Section light(top.table("light"), "light", origin);
  light.text("driver", l.driver, {"none", "gpio", "pwm"});
  light.text("chip", l.gpio_chip);
  light.integer("led_line", l.led_line, 0, 1023, "(line offset on the chip)");
  light.integer("trigger_line", l.trigger_line, -1, 1023, "(-1 = no trigger output)");
  light.boolean("active_low", l.active_low);
  light.text("consumer", l.consumer);
  light.real("trigger_pulse_us", l.trigger_pulse_us, 1.0, 10000.0, "us");
  light.real("spin_us", l.spin_us, 0.0, 1000.0, "us");
  light.real("late_limit_us", l.late_limit_us, 1.0, 100000.0, "us");
  light.text("pwm_sysfs_root", l.pwm_sysfs_root);
  light.integer("pwm_chip", l.pwm_chip, 0, 1023, "(the N of pwmchipN)");
  light.integer("pwm_channel", l.pwm_channel, 0, 1023, "(the M of pwmM)");
  light.finish();
  if (l.driver == "gpio" && l.led_line < 0) {
    throw ConfigError(origin + ": [light] driver = \"gpio\" needs led_line (the LED ring's line on chip " +
                      l.gpio_chip + ", see gpioinfo)");
  }
  if (l.driver == "gpio" && l.trigger_line == l.led_line) {
    throw ConfigError(origin + ": [light] trigger_line and led_line are both " + std::to_string(l.led_line) +
                      ": give the trigger its own line, or -1 for none");
  }
}

// [plausibility]: the vehicle-dynamics gate (plausibility_gate.hpp).
void read_plausibility(Section& top, PlausibilityLimits& p, const std::string& origin) {
  Section s(top.table("plausibility"), "plausibility", origin);
  s.real("max_accel_mps2", p.max_accel_mps2, 1.0, 200.0, "m/s^2");
  s.real("speed_noise_mps", p.speed_noise_mps, 0.0, 10.0, "m/s");
  s.real("speed_noise_fraction", p.speed_noise_fraction, 0.0, 1.0, "(share of the tracked speed)");
  s.real("max_yaw_rate_dps", p.max_yaw_rate_dps, 1.0, 3600.0, "deg/s");
  s.real("direction_noise_deg", p.direction_noise_deg, 0.0, 180.0, "deg");
  s.real("min_direction_speed_mps", p.min_direction_speed_mps, 0.1, 100.0, "m/s");
  s.integer("reacquire_count", p.reacquire_count, 2, 1000, "estimates");
  s.real("track_timeout_ms", p.track_timeout_ms, 10.0, 60000.0, "ms");
  s.finish();
}

}  // namespace

const std::vector<std::string>& log_level_names() {
  static const std::vector<std::string> names{"trace", "debug", "info", "warn", "error", "critical", "off"};
  return names;
}

DaemonConfig parse_config(std::string_view toml_text, const std::string& origin) {
  toml::table root;
  try {
    root = toml::parse(toml_text, origin);
  } catch (const toml::parse_error& e) {
    std::ostringstream msg;
    msg << origin << ':' << e.source().begin.line << ": not valid TOML: " << e.description();
    throw ConfigError(msg.str());
  }

  DaemonConfig c;
  c.origin = origin;
  Section top(&root, "top level", origin);

  Section source(top.table("source"), "source", origin);
  source.text("uri", c.source_uri);
  source.integer("ring_slots", c.ring_slots, 2, 64, "frames");
  source.real("sim_fps", c.sim_fps, 1.0, 1000.0, "frames/s");
  source.integer("sim_seed", c.sim_seed, 0, std::int64_t{1} << 53, "");
  source.text("sim_ground", c.sim_ground);
  source.real("replay_preload_limit_mb", c.replay_preload_limit_mb, 1.0, 65536.0, "MiB");
  source.finish();
  try {
    (void)drivers::sim::parse_ground(c.sim_ground);  // the photo itself is read when the source starts
  } catch (const std::invalid_argument& e) {
    throw ConfigError(origin + ": [source] sim_ground: " + e.what());
  }

  Section can(top.table("can"), "can", origin);
  can.text("uri", c.can_uri);
  can.integer("period_ms", c.period_ms, 1, 1000, "ms");
  can.integer("status_period_ms", c.status_period_ms, 1, 10000, "ms");
  can.real("staleness_limit_ms", c.staleness_limit_ms, 1.0, 1000.0, "ms");
  can.real("late_wakeup_limit_ms", c.late_wakeup_limit_ms, 0.01, 1000.0, "ms");
  can.real("min_quality", c.min_quality, 0.0, 1.0, "(estimator quality; lower goes out with Valid = 0)");
  can.integer("base_id", c.base_id, 0, 0x7FC, "(11-bit CAN ID of GVS_Velocity; 3 more IDs follow)");
  can.finish();
  if (c.status_period_ms % c.period_ms != 0) {
    throw ConfigError(origin + ": [can] status_period_ms (" + std::to_string(c.status_period_ms) +
                      ") must be a multiple of period_ms (" + std::to_string(c.period_ms) + ")");
  }

  Section camera(top.table("camera"), "camera", origin);
  camera.integer("width_px", c.camera.width_px, 16, 8192, "px");
  camera.integer("height_px", c.camera.height_px, 16, 8192, "px");
  camera.real("mm_per_px", c.camera.mm_per_px, 0.001, 10.0, "mm/px");
  camera.real("mount_yaw_deg", c.camera.mount_yaw_deg, -180.0, 180.0, "deg");
  camera.real("lever_arm_x_m", c.lever_arm_x_m, -10.0, 10.0, "m");
  camera.real("lever_arm_y_m", c.lever_arm_y_m, -10.0, 10.0, "m");
  camera.finish();

  Section estimator(top.table("estimator"), "estimator", origin);
  estimator.text("method", c.estimator_method);
  estimator.finish();

  Section exposure(top.table("exposure"), "exposure", origin);
  exposure.text("mode", c.exposure_mode, {"fixed", "adaptive", "double-pulse"});
  exposure.real("initial_us", c.exposure_initial_us, 1.0, 100000.0, "us");
  exposure.real("max_us", c.exposure_max_us, 1.0, 100000.0, "us");
  exposure.real("min_pulse_us", c.exposure_min_pulse_us, 0.1, 1000.0, "us");
  exposure.finish();
  if (!(c.exposure_min_pulse_us <= c.exposure_initial_us && c.exposure_initial_us <= c.exposure_max_us)) {
    throw ConfigError(origin + ": [exposure] needs min_pulse_us <= initial_us <= max_us (got " +
                      fmt_num(c.exposure_min_pulse_us) + ", " + fmt_num(c.exposure_initial_us) + ", " +
                      fmt_num(c.exposure_max_us) + ")");
  }

  Section cam(top.table("libcamera"), "libcamera", origin);
  cam.real("fps", c.libcamera_fps, 1.0, 1000.0, "frames/s");
  cam.text("pixel_format", c.libcamera_pixel_format, {"R8", "YUV420"});
  cam.integer("buffer_count", c.libcamera_buffer_count, 2, 16, "buffers");
  cam.real("exposure_min_us", c.libcamera_exposure_min_us, 1.0, 100000.0, "us");
  cam.real("gain_min", c.libcamera_gain_min, 1.0, 64.0, "");
  cam.real("gain_max", c.libcamera_gain_max, 1.0, 64.0, "");
  cam.real("stall_periods", c.libcamera_stall_periods, 1.0, 100.0, "frame periods");
  cam.real("retry_interval_ms", c.libcamera_retry_interval_ms, 10.0, 60000.0, "ms");
  cam.finish();
  if (c.libcamera_gain_min > c.libcamera_gain_max) {
    throw ConfigError(origin + ": [libcamera] needs gain_min <= gain_max (got " + fmt_num(c.libcamera_gain_min) +
                      ", " + fmt_num(c.libcamera_gain_max) + ")");
  }
  read_light(top, c.light, origin);
  read_plausibility(top, c.plausibility, origin);

  Section threads(top.table("threads"), "threads", origin);
  read_thread(threads, "capture", c.capture_thread, origin);
  read_thread(threads, "processing", c.processing_thread, origin);
  read_thread(threads, "sender", c.sender_thread, origin);
  threads.boolean("lock_memory", c.lock_memory);
  threads.integer("prefault_stack_kb", c.prefault_stack_kb, 0, 8192, "KiB");
  threads.finish();

  Section log(top.table("log"), "log", origin);
  log.text("level", c.log_level, log_level_names());
  log.real("health_interval_s", c.health_interval_s, 0.5, 3600.0, "s");
  log.finish();

  top.finish();
  return c;
}

DaemonConfig load_config_file(const std::filesystem::path& file) {
  std::ifstream in(file);
  if (!in) throw ConfigError(file.string() + ": cannot read the configuration file (does it exist?)");
  std::ostringstream text;
  text << in.rdbuf();
  return parse_config(text.str(), file.string());
}

std::vector<std::string> restart_only_changes(const DaemonConfig& a, const DaemonConfig& b) {
  std::vector<std::string> changed;
  auto check = [&](bool differs, const char* key) {
    if (differs) changed.emplace_back(key);
  };
  check(a.source_uri != b.source_uri, "source.uri");
  check(a.ring_slots != b.ring_slots, "source.ring_slots");
  check(a.sim_fps != b.sim_fps, "source.sim_fps");
  check(a.sim_seed != b.sim_seed, "source.sim_seed");
  check(a.sim_ground != b.sim_ground, "source.sim_ground");
  check(a.replay_preload_limit_mb != b.replay_preload_limit_mb, "source.replay_preload_limit_mb");
  check(a.can_uri != b.can_uri, "can.uri");
  check(a.period_ms != b.period_ms, "can.period_ms");
  check(a.status_period_ms != b.status_period_ms, "can.status_period_ms");
  check(a.base_id != b.base_id, "can.base_id");
  check(a.camera.width_px != b.camera.width_px, "camera.width_px");
  check(a.camera.height_px != b.camera.height_px, "camera.height_px");
  check(a.camera.mm_per_px != b.camera.mm_per_px, "camera.mm_per_px");
  check(a.camera.mount_yaw_deg != b.camera.mount_yaw_deg, "camera.mount_yaw_deg");
  check(a.lever_arm_x_m != b.lever_arm_x_m, "camera.lever_arm_x_m");
  check(a.lever_arm_y_m != b.lever_arm_y_m, "camera.lever_arm_y_m");
  check(a.estimator_method != b.estimator_method, "estimator.method");
  check(a.libcamera_fps != b.libcamera_fps || a.libcamera_pixel_format != b.libcamera_pixel_format ||
            a.libcamera_buffer_count != b.libcamera_buffer_count ||
            a.libcamera_exposure_min_us != b.libcamera_exposure_min_us || a.libcamera_gain_min != b.libcamera_gain_min ||
            a.libcamera_gain_max != b.libcamera_gain_max || a.libcamera_stall_periods != b.libcamera_stall_periods ||
            a.libcamera_retry_interval_ms != b.libcamera_retry_interval_ms,
        "libcamera");
  check(a.light != b.light, "light");
  check(a.capture_thread.priority != b.capture_thread.priority || a.capture_thread.cpu != b.capture_thread.cpu,
        "threads.capture");
  check(a.processing_thread.priority != b.processing_thread.priority ||
            a.processing_thread.cpu != b.processing_thread.cpu,
        "threads.processing");
  check(a.sender_thread.priority != b.sender_thread.priority || a.sender_thread.cpu != b.sender_thread.cpu,
        "threads.sender");
  check(a.lock_memory != b.lock_memory, "threads.lock_memory");
  check(a.prefault_stack_kb != b.prefault_stack_kb, "threads.prefault_stack_kb");
  return changed;
}

}  // namespace gvs::daemon
