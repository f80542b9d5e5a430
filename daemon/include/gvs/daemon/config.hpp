// gvsd's configuration: a TOML file (systemd/gvsd.toml is the documented
// example), then the command line on top. The keys, their ranges and which
// SIGHUP applies are declared in config_keys.hpp's table; the defaults are
// the initializers below.
#pragma once

#include <cstdint>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "gvs/daemon/plausibility_gate.hpp"
#include "gvs/drivers/strobe.hpp"
#include "gvs/core/frame.hpp"

namespace gvs::daemon {

/// A configuration that cannot be used. The message names the file, line,
/// key and the allowed values.
class ConfigError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Scheduling of one real-time thread. priority 0 = normal scheduling
/// (SCHED_OTHER), 1..99 = SCHED_FIFO; cpu -1 = any CPU.
struct ThreadConfig {
  int priority = 0;
  int cpu = -1;
};

/// [height]: where the camera's height comes from: the head's laser dots
/// (docs/estimator.md, "Height from the laser dots") or an external distance
/// sensor on CAN (docs/can-interface.md, "External height"), its signal as a
/// DBC line describes it.
struct HeightConfig {
  std::string source = "none";  ///< none | can | lasers
  std::string lasers_file;      ///< lasers: the beams' geometry (gvs calibrate height --out, or a camera.json)
  std::string interface;        ///< SocketCAN interface; empty = the one of [can] uri
  std::uint32_t can_id = 0x520;
  bool extended = false;
  int start_bit = 0;
  int length = 16;
  std::string byte_order = "intel";  ///< intel (@1) | motorola (@0)
  bool is_signed = false;
  double scale = 0.01;    ///< mm per raw step
  double offset_mm = 0.0; ///< height = raw * scale + offset_mm: the camera's optical centre above the ground
  double nominal_mm = 60.0;  ///< the camera's height when [camera] mm_per_px was calibrated
  double max_gap_ms = 20.0;  ///< samples further apart (or older) than this: no height, the scale stays nominal
};

struct DaemonConfig {
  std::string origin = "(built-in defaults)";  ///< file the values came from

  // [source]
  std::string source_uri = "sim:sine";
  int ring_slots = 4;
  double sim_fps = 60.0;
  std::int64_t sim_seed = 1;
  std::string sim_body = "flat";  ///< flat | heave | ride (drivers::body_motion_names)
  std::string sim_ground = "procedural";  ///< or "photo:FILE[:MM_PER_PIXEL]" (drivers::sim::parse_ground)
  double replay_window_mb = 16.0;

  // [can]
  std::string can_uri = "candump:-";
  int period_ms = 20;
  int status_period_ms = 100;
  bool align_to_frames = false;
  double staleness_limit_ms = 50.0;
  double late_wakeup_limit_ms = 1.0;
  double min_quality = 0.3;
  std::uint32_t base_id = 0x300;      ///< CAN ID of GVS_Velocity; the others follow (can/gvs.dbc)

  // [camera]
  core::CameraGeometry camera;
  double lever_arm_x_m = 0.0;  ///< sensor position relative to the car's reference point, vehicle axes
  double lever_arm_y_m = 0.0;

  // [height]
  HeightConfig height;

  // [estimator]
  std::string estimator_method = "gvs";

  // [exposure] (dsp/exposure_control.hpp)
  std::string exposure_mode = "double-pulse";  ///< fixed | adaptive | double-pulse
  double exposure_initial_us = 3000.0;
  double exposure_max_us = 3000.0;     ///< longest continuous exposure
  double exposure_min_pulse_us = 2.0;  ///< shortest LED pulse

  // [libcamera] (source libcamera[:ID])
  double libcamera_fps = 60.0;
  std::string libcamera_pixel_format = "YUV420";  ///< YUV420 (through the ISP) | R8 (8-bit mono raw)
  int libcamera_buffer_count = 4;
  double libcamera_exposure_min_us = 10.0;
  double libcamera_gain_min = 1.0;
  double libcamera_gain_max = 8.0;
  double libcamera_stall_periods = 3.0;
  double libcamera_retry_interval_ms = 500.0;
  // [light] LED ring and trigger (drivers/strobe.hpp)
  drivers::StrobeConfig light;

  // [plausibility] (plausibility_gate.hpp)
  PlausibilityLimits plausibility;

  // [threads]
  ThreadConfig capture_thread{80, -1};
  ThreadConfig processing_thread{70, -1};
  ThreadConfig sender_thread{90, -1};
  bool lock_memory = true;
  bool lock_on_fault = true;
  int stack_kb = 1024;
  int prefault_stack_kb = 256;

  // [log]
  std::string log_level = "info";
  double health_interval_s = 5.0;

  // command line only
  double run_for_s = 0.0;  ///< 0: until stopped
};

/// Parses TOML text; `origin` names it in messages (usually the file path).
DaemonConfig parse_config(std::string_view toml_text, const std::string& origin);
/// Reads and parses a file. Throws ConfigError (also when it cannot be read).
DaemonConfig load_config_file(const std::filesystem::path& file);

/// Keys that differ between `running` and `reloaded` but only take effect
/// at a restart (by key, e.g. "source.uri"; config_keys.hpp says which).
std::vector<std::string> restart_only_changes(const DaemonConfig& running,
                                              const DaemonConfig& reloaded);

/// SIGHUP: copies every key SIGHUP applies from `reloaded` into `running`
/// and returns the changed ones ("can.min_quality = 0.4 (was 0.3)").
std::vector<std::string> apply_reloadable_keys(DaemonConfig& running, const DaemonConfig& reloaded);

/// The list of log levels accepted in [log] level.
const std::vector<std::string>& log_level_names();

}  // namespace gvs::daemon
