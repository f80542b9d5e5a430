// The table of gvsd's configuration keys: every key once. Parsing
// (config.cpp), SIGHUP, the example file and the reference (config_text.cpp)
// read it; adding a key here is all it takes to have it everywhere.
#include "gvs/daemon/config_keys.hpp"

#include <array>
#include <stdexcept>

#include <fmt/format.h>

#include "gvs/daemon/config.hpp"
#include "gvs/daemon/external_height.hpp"
#include "gvs/drivers/sim/ground_spec.hpp"
#include "gvs/drivers/simulator.hpp"
#include "gvs/dsp/estimator.hpp"

namespace gvs::daemon {

namespace {

// Where a key lives in DaemonConfig, as a function the table can hold.
#define GVS_FIELD(member) [](DaemonConfig& c) -> ConfigField { return &c.member; }

constexpr double kMaxSeed = 9007199254740992.0;  // 2^53: every seed a double holds exactly

std::vector<std::string> estimator_methods() {
  std::vector<std::string> m = dsp::estimator_names();
  m.emplace_back("truth");
  return m;
}
std::vector<std::string> exposure_modes() { return {"fixed", "adaptive", "double-pulse"}; }
std::vector<std::string> pixel_formats() { return {"R8", "YUV420"}; }
std::vector<std::string> light_drivers() { return {"none", "gpio", "pwm"}; }
std::vector<std::string> log_levels() { return log_level_names(); }
std::vector<std::string> height_sources() { return {"none", "can", "lasers"}; }
std::vector<std::string> sim_bodies() { return drivers::body_motion_names(); }
std::vector<std::string> byte_orders() { return {"intel", "motorola"}; }

const std::array kSections{
    ConfigSection{"source",
                  "Where frames come from:\n"
                  "  sim:SCENARIO    the simulator (const, sine, accel, brake, skidpad, crawl, stop, spin), looping\n"
                  "  replay:DIR      a gvs-dataset folder, paced by its timestamps; gvsd stops at its end\n"
                  "  libcamera[:ID]  the real camera: by id, or the first one; see [libcamera]"},
    ConfigSection{"can",
                  "Where the messages of can/gvs.dbc go:\n"
                  "  socketcan:IFACE  a SocketCAN interface (can0, vcan0, ...)\n"
                  "  candump:PATH     a `candump -L` log file; candump:- writes to stdout"},
    ConfigSection{"plausibility",
                  "The vehicle-dynamics gate behind the estimator (docs/daemon.md, \"Plausibility gate\").\n"
                  "An estimate whose speed differs from the tracked one by more than\n"
                  "max_accel_mps2 * dt + max(speed_noise_mps, speed_noise_fraction * tracked speed),\n"
                  "or whose direction turned faster than a car can, goes out with every Valid bit 0,\n"
                  "is counted and raises GVS_FaultImplausible."},
    ConfigSection{"camera",
                  "Camera geometry (replay takes the dataset's camera.json instead) and the sensor's\n"
                  "position relative to the car's reference point, vehicle axes (x forward, y left):\n"
                  "the velocity is moved there with the yaw rate, v_ref = v_sensor - omega x r.\n"
                  "Only an estimate that has a yaw rate is moved: a frame pair at a crawl (up to\n"
                  "about 3 km/h at 60 fps, where its yaw rate's standard error is at most 3 deg/s;\n"
                  "docs/estimator.md, \"Yaw rate\") or a standstill. Every other goes out as measured\n"
                  "at the sensor, off the reference point's velocity by omega x r (a 9 m skidpad at\n"
                  "12 m/s with 1 m of lever arm: 1.3 m/s sideways, 6 deg of direction): mount the head\n"
                  "at the reference point, or move its velocity in the ECU with the car's yaw rate."},
    ConfigSection{"height",
                  "Where the camera's height comes from; each estimate's speed is scaled by\n"
                  "height / nominal_mm (the ground scale is proportional to the height).\n"
                  "  lasers  the head's laser dots, found in every frame (docs/estimator.md, \"Height from\n"
                  "          the laser dots\"): height, pitch and roll, GVS_ScaleSource = laser_dots;\n"
                  "          lasers_file is what `gvs calibrate height --out` wrote (or a camera.json)\n"
                  "  can     an external distance sensor on CAN (docs/can-interface.md, \"External\n"
                  "          height\"), at each estimate's mid-exposure instant, interpolated between\n"
                  "          the sensor's frames: GVS_ScaleSource = external. The signal is given as\n"
                  "          its DBC line gives it: SG_ H : 7|16@0+ (0.01,0) is start_bit 7, length 16,\n"
                  "          motorola, scale 0.01\n"
                  "Without a height for a frame the scale stays nominal and GVS_FaultScaleUncorrected\n"
                  "says so."},
    ConfigSection{"estimator", "How a frame becomes a velocity (docs/estimator.md)."},
    ConfigSection{"exposure",
                  "Closed loop: the processing thread plans the next exposure from the latest estimate\n"
                  "(dsp/exposure_control.hpp); the simulated camera obeys it. double-pulse measures speed\n"
                  "best (docs/accuracy.md) but needs a strobe: with the camera and [light] driver = \"none\",\n"
                  "gvsd uses adaptive (one continuous exposure that follows the speed) instead."},
    ConfigSection{"libcamera",
                  "The camera of source libcamera[:ID] (docs/hardware.md, \"Camera (libcamera)\").\n"
                  "Stream size = [camera] width_px x height_px, exactly. Manual exposure: ExposureTime =\n"
                  "the exposure plan clamped to [exposure_min_us, min([exposure] max_us, 0.9 frame period)],\n"
                  "AnalogueGain = gain_min * max_us / ExposureTime clamped to [gain_min, gain_max],\n"
                  "FrameDurationLimits = 1/fps."},
    ConfigSection{"light",
                  "The LED ring and the global-shutter camera's trigger input (docs/hardware.md,\n"
                  "\"Light and trigger\"). Each frame's exposure plan is fired on the capture thread:\n"
                  "trigger pulse, then the LED on for the exposure or at the plan's pulses."},
    ConfigSection{"threads",
                  "Without the privilege (CAP_SYS_NICE, CAP_IPC_LOCK) gvsd warns once and runs anyway."},
    ConfigSection{"threads.capture", "The capture thread's scheduling."},
    ConfigSection{"threads.processing", "The processing thread's scheduling."},
    ConfigSection{"threads.sender", "The CAN sender thread's scheduling."},
    ConfigSection{"log", "The log (stderr; the journal under systemd)."},
};

using enum Reload;

// Each entry names only the fields it sets; GCC 12 warns about the others
// even though they have default member initializers.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"
const std::array kKeys{
    // [source]
    ConfigKey{.section = "source", .name = "uri", .field = GVS_FIELD(source_uri), .reload = restart,
              .help = "frame source: sim:SCENARIO | replay:DIR | libcamera[:ID] (--source overrides it)"},
    ConfigKey{.section = "source", .name = "ring_slots", .field = GVS_FIELD(ring_slots), .min = 2, .max = 64,
              .unit = "frames", .reload = restart, .help = "preallocated frame buffers between capture and processing"},
    ConfigKey{.section = "source", .name = "sim_fps", .field = GVS_FIELD(sim_fps), .min = 1, .max = 1000,
              .unit = "frames/s", .reload = restart, .help = "simulated camera frame rate"},
    ConfigKey{.section = "source", .name = "sim_seed", .field = GVS_FIELD(sim_seed), .min = 0, .max = kMaxSeed,
              .reload = restart, .help = "simulated asphalt and noise"},
    ConfigKey{.section = "source", .name = "sim_ground", .field = GVS_FIELD(sim_ground), .reload = restart,
              .help = "\"procedural\" or \"photo:FILE[:MM_PER_PIXEL]\", a seamless asphalt photo (docs/simulator.md)"},
    ConfigKey{.section = "source", .name = "sim_body", .field = GVS_FIELD(sim_body), .allowed = sim_bodies,
              .reload = restart,
              .help = "the simulated car's body motion: flat, heave (+-5 mm at 1-5 Hz) or ride (heave, pitch, roll, a kerb)"},
    ConfigKey{.section = "source", .name = "replay_window_mb", .field = GVS_FIELD(replay_window_mb), .min = 1,
              .max = 4096, .unit = "MiB", .reload = restart,
              .help = "replay: frames decoded ahead of the capture thread (at least 4), by a decoder thread at "
                      "normal scheduling"},
    // [can]
    ConfigKey{.section = "can", .name = "uri", .field = GVS_FIELD(can_uri), .reload = restart,
              .help = "CAN output: socketcan:IFACE | candump:PATH (--can overrides it)"},
    ConfigKey{.section = "can", .name = "base_id", .field = GVS_FIELD(base_id), .min = 0, .max = 0x7FB, .reload = restart,
              .help = "11-bit CAN ID of GVS_Velocity; GVS_VelocityXY, GVS_Status, GVS_Timing, GVS_RideHeight follow",
              .hex = true},
    ConfigKey{.section = "can", .name = "period_ms", .field = GVS_FIELD(period_ms), .min = 4, .max = 100,
              .unit = "ms", .reload = restart,
              .help = "velocity messages, on an absolute schedule (the ECU expects 20)"},
    ConfigKey{.section = "can", .name = "align_to_frames", .field = GVS_FIELD(align_to_frames), .reload = restart,
              .help = "move the velocity messages' slots to just after the estimates are published (the period "
                      "stays period_ms, each within 0.1 ms); needs a frame rate that is a multiple or a divisor "
                      "of the CAN rate (50 Hz: 25, 50, 100, 250 fps)"},
    ConfigKey{.section = "can", .name = "status_period_ms", .field = GVS_FIELD(status_period_ms), .min = 1,
              .max = 10000, .unit = "ms", .reload = restart, .help = "status and timing messages, a multiple of period_ms"},
    ConfigKey{.section = "can", .name = "staleness_limit_ms", .field = GVS_FIELD(staleness_limit_ms), .min = 1,
              .max = 1000, .unit = "ms", .reload = sighup, .help = "older estimates go out with every Valid bit 0"},
    ConfigKey{.section = "can", .name = "late_wakeup_limit_ms", .field = GVS_FIELD(late_wakeup_limit_ms),
              .min = 0.01, .max = 1000, .unit = "ms", .reload = sighup,
              .help = "a sender wake-up later than this counts as late"},
    ConfigKey{.section = "can", .name = "min_quality", .field = GVS_FIELD(min_quality), .min = 0, .max = 1,
              .reload = sighup,
              .help = "estimates of lower quality go out with every Valid bit 0 (docs/can-interface.md, \"Validity\")",
              .note = "0 = quality never decides"},
    // [plausibility]
    ConfigKey{.section = "plausibility", .name = "max_accel_mps2", .field = GVS_FIELD(plausibility.max_accel_mps2),
              .min = 1, .max = 200, .unit = "m/s^2", .reload = sighup,
              .help = "3 g: beyond the grip of any car on the ground, aero included"},
    ConfigKey{.section = "plausibility", .name = "speed_noise_mps", .field = GVS_FIELD(plausibility.speed_noise_mps),
              .min = 0, .max = 10, .unit = "m/s", .reload = sighup, .help = "measurement allowance at low speed"},
    ConfigKey{.section = "plausibility", .name = "speed_noise_fraction",
              .field = GVS_FIELD(plausibility.speed_noise_fraction), .min = 0, .max = 1, .reload = sighup,
              .help = "measurement allowance, share of the tracked speed"},
    ConfigKey{.section = "plausibility", .name = "max_yaw_rate_dps",
              .field = GVS_FIELD(plausibility.max_yaw_rate_dps), .min = 1, .max = 3600, .unit = "deg/s",
              .reload = sighup, .help = "fastest the vehicle axes turn (a spin)"},
    ConfigKey{.section = "plausibility", .name = "direction_noise_deg",
              .field = GVS_FIELD(plausibility.direction_noise_deg), .min = 0, .max = 180, .unit = "deg",
              .reload = sighup, .help = "measurement allowance of the direction"},
    ConfigKey{.section = "plausibility", .name = "min_direction_speed_mps",
              .field = GVS_FIELD(plausibility.min_direction_speed_mps), .min = 0.1, .max = 100, .unit = "m/s",
              .reload = sighup, .help = "below, the direction is not checked"},
    ConfigKey{.section = "plausibility", .name = "reacquire_count", .field = GVS_FIELD(plausibility.reacquire_count),
              .min = 2, .max = 1000, .unit = "estimates", .reload = sighup,
              .help = "agreeing rejected estimates in a row that become the track"},
    ConfigKey{.section = "plausibility", .name = "track_timeout_ms",
              .field = GVS_FIELD(plausibility.track_timeout_ms), .min = 10, .max = 60000, .unit = "ms", .reload = sighup,
              .help = "a track this old is dropped; the next estimate starts a new one"},
    // [camera]
    ConfigKey{.section = "camera", .name = "width_px", .field = GVS_FIELD(camera.width_px), .min = 16, .max = 8192,
              .unit = "px", .reload = restart, .help = "frame width"},
    ConfigKey{.section = "camera", .name = "height_px", .field = GVS_FIELD(camera.height_px), .min = 16,
              .max = 8192, .unit = "px", .reload = restart, .help = "frame height"},
    ConfigKey{.section = "camera", .name = "mm_per_px", .field = GVS_FIELD(camera.mm_per_px), .min = 0.001,
              .max = 10, .unit = "mm/px", .reload = restart, .help = "ground sampling distance"},
    ConfigKey{.section = "camera", .name = "mount_yaw_deg", .field = GVS_FIELD(camera.mount_yaw_deg), .min = -180,
              .max = 180, .unit = "deg", .reload = restart, .help = "camera rotation about z, CCW from above"},
    ConfigKey{.section = "camera", .name = "lever_arm_x_m", .field = GVS_FIELD(lever_arm_x_m), .min = -10,
              .max = 10, .unit = "m", .reload = restart, .help = "sensor ahead of the reference point"},
    ConfigKey{.section = "camera", .name = "lever_arm_y_m", .field = GVS_FIELD(lever_arm_y_m), .min = -10,
              .max = 10, .unit = "m", .reload = restart, .help = "sensor left of the reference point"},
    // [height]
    ConfigKey{.section = "height", .name = "source", .field = GVS_FIELD(height.source), .allowed = height_sources,
              .reload = restart,
              .help = "lasers: the head's laser dots; can: an external distance sensor's frames; none: no height"},
    ConfigKey{.section = "height", .name = "lasers_file", .field = GVS_FIELD(height.lasers_file), .reload = restart,
              .help = "the laser dots' geometry: `gvs calibrate height --out` JSON, or a camera.json",
              .only_when = "source = \"lasers\"", .example = "\"/etc/gvsd/lasers.json\""},
    ConfigKey{.section = "height", .name = "interface", .field = GVS_FIELD(height.interface), .reload = restart,
              .help = "SocketCAN interface it is received on", .only_when = "source = \"can\"",
              .example = "\"can0\"", .note = "empty = the interface of [can] uri"},
    ConfigKey{.section = "height", .name = "can_id", .field = GVS_FIELD(height.can_id), .min = 0, .max = 0x1FFFFFFF,
              .reload = restart, .help = "the sensor's message", .only_when = "source = \"can\"", .hex = true},
    ConfigKey{.section = "height", .name = "extended", .field = GVS_FIELD(height.extended), .reload = restart,
              .help = "29-bit identifier", .only_when = "source = \"can\""},
    ConfigKey{.section = "height", .name = "start_bit", .field = GVS_FIELD(height.start_bit), .min = 0, .max = 63,
              .reload = restart, .help = "the signal's DBC start bit", .only_when = "source = \"can\""},
    ConfigKey{.section = "height", .name = "length", .field = GVS_FIELD(height.length), .min = 1, .max = 32,
              .unit = "bits", .reload = restart, .help = "the signal's length", .only_when = "source = \"can\""},
    ConfigKey{.section = "height", .name = "byte_order", .field = GVS_FIELD(height.byte_order),
              .allowed = byte_orders, .reload = restart, .help = "intel (@1) or motorola (@0)",
              .only_when = "source = \"can\""},
    ConfigKey{.section = "height", .name = "signed", .field = GVS_FIELD(height.is_signed), .reload = restart,
              .help = "two's complement (-) or unsigned (+)", .only_when = "source = \"can\""},
    ConfigKey{.section = "height", .name = "scale", .field = GVS_FIELD(height.scale), .min = -1000, .max = 1000,
              .unit = "mm", .reload = restart, .help = "mm per raw step", .only_when = "source = \"can\""},
    ConfigKey{.section = "height", .name = "offset_mm", .field = GVS_FIELD(height.offset_mm), .min = -10000,
              .max = 10000, .unit = "mm", .reload = restart,
              .help = "height = raw * scale + offset_mm, of the camera's optical centre above the ground",
              .only_when = "source = \"can\""},
    ConfigKey{.section = "height", .name = "nominal_mm", .field = GVS_FIELD(height.nominal_mm), .min = 1,
              .max = 10000, .unit = "mm", .reload = restart,
              .help = "the camera's height when [camera] mm_per_px was calibrated",
              .only_when = "source = \"can\" or \"lasers\""},
    ConfigKey{.section = "height", .name = "max_gap_ms", .field = GVS_FIELD(height.max_gap_ms), .min = 0.1,
              .max = 1000, .unit = "ms", .reload = restart,
              .help = "samples further apart, or older, than this give no height", .only_when = "source = \"can\""},
    // [estimator]
    ConfigKey{.section = "estimator", .name = "method", .field = GVS_FIELD(estimator_method),
              .allowed = estimator_methods, .reload = restart,
              .help = "gvs is the product; thesis-fft, thesis-laplacian for comparison (the thesis's ORB methods, "
                      "thesis and thesis-orb, are in the desk tool only: gvs replay --method); truth = the "
                      "source's ground truth (pipeline tests)"},
    // [exposure]
    ConfigKey{.section = "exposure", .name = "mode", .field = GVS_FIELD(exposure_mode), .allowed = exposure_modes,
              .reload = sighup, .help = "exposure controller"},
    ConfigKey{.section = "exposure", .name = "initial_us", .field = GVS_FIELD(exposure_initial_us), .min = 1,
              .max = 100000, .unit = "us", .reload = restart, .help = "first frames' exposure"},
    ConfigKey{.section = "exposure", .name = "max_us", .field = GVS_FIELD(exposure_max_us), .min = 1,
              .max = 100000, .unit = "us", .reload = sighup, .help = "longest continuous exposure"},
    ConfigKey{.section = "exposure", .name = "min_pulse_us", .field = GVS_FIELD(exposure_min_pulse_us), .min = 0.1,
              .max = 1000, .unit = "us", .reload = sighup, .help = "shortest LED pulse"},
    // [libcamera]
    ConfigKey{.section = "libcamera", .name = "fps", .field = GVS_FIELD(libcamera_fps), .min = 1, .max = 1000,
              .unit = "frames/s", .reload = restart, .help = "frame rate"},
    ConfigKey{.section = "libcamera", .name = "pixel_format", .field = GVS_FIELD(libcamera_pixel_format),
              .allowed = pixel_formats, .reload = restart,
              .help = "YUV420 (its Y plane, through the ISP) or R8 (8-bit mono raw stream)"},
    ConfigKey{.section = "libcamera", .name = "buffer_count", .field = GVS_FIELD(libcamera_buffer_count), .min = 2,
              .max = 16, .unit = "buffers", .reload = restart, .help = "mapped buffers = reusable requests"},
    ConfigKey{.section = "libcamera", .name = "exposure_min_us", .field = GVS_FIELD(libcamera_exposure_min_us),
              .min = 1, .max = 100000, .unit = "us", .reload = restart, .help = "shortest ExposureTime sent"},
    ConfigKey{.section = "libcamera", .name = "gain_min", .field = GVS_FIELD(libcamera_gain_min), .min = 1,
              .max = 64, .reload = restart, .help = "AnalogueGain at [exposure] max_us"},
    ConfigKey{.section = "libcamera", .name = "gain_max", .field = GVS_FIELD(libcamera_gain_max), .min = 1,
              .max = 64, .reload = restart, .help = "AnalogueGain never above this"},
    ConfigKey{.section = "libcamera", .name = "stall_periods", .field = GVS_FIELD(libcamera_stall_periods),
              .min = 1, .max = 100, .unit = "frame periods", .reload = restart,
              .help = "no frame for this long: a source error (camera fault)"},
    ConfigKey{.section = "libcamera", .name = "retry_interval_ms", .field = GVS_FIELD(libcamera_retry_interval_ms),
              .min = 10, .max = 60000, .unit = "ms", .reload = restart,
              .help = "re-open backoff when the camera is gone; a camera silent this long is restarted"},
    // [light]
    ConfigKey{.section = "light", .name = "driver", .field = GVS_FIELD(light.driver), .allowed = light_drivers,
              .reload = restart, .help = "gpio (libgpiod, user-space timed) or pwm (hardware-timed, single pulse)"},
    ConfigKey{.section = "light", .name = "chip", .field = GVS_FIELD(light.gpio_chip), .reload = restart,
              .help = "GPIO chip: name, number or /dev path (gpiodetect lists them)", .only_when = "driver = \"gpio\""},
    ConfigKey{.section = "light", .name = "led_line", .field = GVS_FIELD(light.led_line), .min = 0, .max = 1023,
              .reload = restart, .help = "the LED driver's line on the chip (gpioinfo); required",
              .only_when = "driver = \"gpio\"", .example = "17"},
    ConfigKey{.section = "light", .name = "trigger_line", .field = GVS_FIELD(light.trigger_line), .min = -1,
              .max = 1023, .reload = restart, .help = "the camera's trigger input line", .only_when = "driver = \"gpio\"",
              .note = "-1 = no trigger output"},
    ConfigKey{.section = "light", .name = "active_low", .field = GVS_FIELD(light.active_low), .reload = restart,
              .help = "both lines are driven low when on", .only_when = "driver = \"gpio\" or \"pwm\""},
    ConfigKey{.section = "light", .name = "consumer", .field = GVS_FIELD(light.consumer), .reload = restart,
              .help = "the lines' user as gpioinfo shows it", .only_when = "driver = \"gpio\""},
    ConfigKey{.section = "light", .name = "trigger_pulse_us", .field = GVS_FIELD(light.trigger_pulse_us), .min = 1,
              .max = 10000, .unit = "us", .reload = restart, .help = "width of the trigger pulse",
              .only_when = "driver = \"gpio\""},
    ConfigKey{.section = "light", .name = "spin_us", .field = GVS_FIELD(light.spin_us), .min = 0, .max = 1000,
              .unit = "us", .reload = restart, .help = "busy-wait before an edge after the sleep (above cyclictest p99)",
              .only_when = "driver = \"gpio\""},
    ConfigKey{.section = "light", .name = "late_limit_us", .field = GVS_FIELD(light.late_limit_us), .min = 1,
              .max = 100000, .unit = "us", .reload = restart, .help = "an edge later than this counts as late",
              .only_when = "driver = \"gpio\""},
    ConfigKey{.section = "light", .name = "pwm_sysfs_root", .field = GVS_FIELD(light.pwm_sysfs_root), .reload = restart,
              .help = "Linux PWM sysfs (period = frame period, duty = the pulse; no double pulse)",
              .only_when = "driver = \"pwm\""},
    ConfigKey{.section = "light", .name = "pwm_chip", .field = GVS_FIELD(light.pwm_chip), .min = 0, .max = 1023,
              .reload = restart, .help = "the N of pwmchipN", .only_when = "driver = \"pwm\""},
    ConfigKey{.section = "light", .name = "pwm_channel", .field = GVS_FIELD(light.pwm_channel), .min = 0,
              .max = 1023, .reload = restart, .help = "the M of pwmM", .only_when = "driver = \"pwm\""},
    // [threads]
    ConfigKey{.section = "threads", .name = "lock_memory", .field = GVS_FIELD(lock_memory), .reload = restart,
              .help = "mlockall(MCL_CURRENT | MCL_FUTURE): no page gvsd has touched is ever swapped out or dropped"},
    ConfigKey{.section = "threads", .name = "lock_on_fault", .field = GVS_FIELD(lock_on_fault), .reload = restart,
              .help = "lock pages as they are first touched (MCL_ONFAULT) instead of making every mapping resident "
                      "whole: the libraries' code gvsd never runs stays out of RAM (gvsd's own code and static data, "
                      "about 1.6 MB, are locked whole); a page first touched after start-up faults once, "
                      "counted as the thread's `page faults` in the health line",
              .only_when = "lock_memory = true"},
    ConfigKey{.section = "threads", .name = "stack_kb", .field = GVS_FIELD(stack_kb), .min = 128, .max = 16384,
              .unit = "KiB", .reload = restart,
              .help = "stack of the threads gvsd and libcamera start (glibc's default is RLIMIT_STACK, 8 MiB, "
                      "which memory locked whole, lock_on_fault = false, makes resident)"},
    ConfigKey{.section = "threads", .name = "prefault_stack_kb", .field = GVS_FIELD(prefault_stack_kb), .min = 0,
              .max = 8192, .unit = "KiB", .reload = restart, .help = "stack touched by each RT thread before its loop"},
    ConfigKey{.section = "threads.capture", .name = "priority", .field = GVS_FIELD(capture_thread.priority), .min = 0,
              .max = 99, .reload = restart, .help = "the capture thread's scheduling priority",
              .note = "0 = normal scheduling, 1..99 = SCHED_FIFO"},
    ConfigKey{.section = "threads.capture", .name = "cpu", .field = GVS_FIELD(capture_thread.cpu), .min = -1, .max = 1023,
              .reload = restart, .help = "the CPU the capture thread runs on", .note = "-1 = any CPU"},
    ConfigKey{.section = "threads.processing", .name = "priority", .field = GVS_FIELD(processing_thread.priority), .min = 0,
              .max = 99, .reload = restart, .help = "the processing thread's scheduling priority",
              .note = "0 = normal scheduling, 1..99 = SCHED_FIFO"},
    ConfigKey{.section = "threads.processing", .name = "cpu", .field = GVS_FIELD(processing_thread.cpu), .min = -1, .max = 1023,
              .reload = restart, .help = "the CPU the processing thread runs on", .note = "-1 = any CPU"},
    ConfigKey{.section = "threads.sender", .name = "priority", .field = GVS_FIELD(sender_thread.priority), .min = 0,
              .max = 99, .reload = restart, .help = "the CAN sender thread's scheduling priority",
              .note = "0 = normal scheduling, 1..99 = SCHED_FIFO"},
    ConfigKey{.section = "threads.sender", .name = "cpu", .field = GVS_FIELD(sender_thread.cpu), .min = -1, .max = 1023,
              .reload = restart, .help = "the CPU the CAN sender thread runs on", .note = "-1 = any CPU"},
    // [log]
    ConfigKey{.section = "log", .name = "level", .field = GVS_FIELD(log_level), .allowed = log_levels, .reload = sighup,
              .help = "least severe level logged"},
    ConfigKey{.section = "log", .name = "health_interval_s", .field = GVS_FIELD(health_interval_s), .min = 0.5,
              .max = 3600, .unit = "s", .reload = sighup, .help = "health line period"},
};
#pragma GCC diagnostic pop

#undef GVS_FIELD

std::string fmt_num(double v) { return fmt::format("{}", v); }

void check_sim_ground(const DaemonConfig& c) {
  try {
    (void)drivers::sim::parse_ground(c.sim_ground);  // the photo itself is read when the source starts
  } catch (const std::invalid_argument& e) {
    throw ConfigError(c.origin + ": [source] sim_ground: " + e.what());
  }
}

void check_status_period(const DaemonConfig& c) {
  if (c.status_period_ms % c.period_ms != 0) {
    throw ConfigError(c.origin + ": [can] status_period_ms (" + std::to_string(c.status_period_ms) +
                      ") must be a multiple of period_ms (" + std::to_string(c.period_ms) + ")");
  }
}

void check_exposure_order(const DaemonConfig& c) {
  if (!(c.exposure_min_pulse_us <= c.exposure_initial_us && c.exposure_initial_us <= c.exposure_max_us)) {
    throw ConfigError(c.origin + ": [exposure] needs min_pulse_us <= initial_us <= max_us (got " +
                      fmt_num(c.exposure_min_pulse_us) + ", " + fmt_num(c.exposure_initial_us) + ", " +
                      fmt_num(c.exposure_max_us) + ")");
  }
}

void check_gain_order(const DaemonConfig& c) {
  if (c.libcamera_gain_min > c.libcamera_gain_max) {
    throw ConfigError(c.origin + ": [libcamera] needs gain_min <= gain_max (got " + fmt_num(c.libcamera_gain_min) +
                      ", " + fmt_num(c.libcamera_gain_max) + ")");
  }
}

void check_prefault_within_stack(const DaemonConfig& c) {
  if (2 * c.prefault_stack_kb > c.stack_kb) {
    throw ConfigError(c.origin + ": [threads] prefault_stack_kb (" + std::to_string(c.prefault_stack_kb) +
                      ") must be at most half of stack_kb (" + std::to_string(c.stack_kb) +
                      "): the rest is the loops' own frames and the thread's TLS");
  }
}

void check_gpio_lines(const DaemonConfig& c) {
  const drivers::StrobeConfig& l = c.light;
  if (l.driver == "gpio" && l.led_line < 0) {
    throw ConfigError(c.origin + ": [light] driver = \"gpio\" needs led_line (the LED ring's line on chip " +
                      l.gpio_chip + ", see gpioinfo)");
  }
  if (l.driver == "gpio" && l.trigger_line == l.led_line) {
    throw ConfigError(c.origin + ": [light] trigger_line and led_line are both " + std::to_string(l.led_line) +
                      ": give the trigger its own line, or -1 for none");
  }
}

void check_external_height(const DaemonConfig& c) {
  if (c.height.source != "can") return;
  try {
    can::validate(external_height_signal(c.height));
  } catch (const std::invalid_argument& e) {
    throw ConfigError(c.origin + ": [height] " + e.what());
  }
  if (c.height.interface.empty() && c.can_uri.rfind("socketcan:", 0) != 0) {
    throw ConfigError(c.origin + ": [height] source = \"can\" needs interface (the CAN interface the sensor is on), "
                      "or a [can] uri = \"socketcan:IFACE\" to share");
  }
}

void check_lasers_file(const DaemonConfig& c) {
  if (c.height.source == "lasers" && c.height.lasers_file.empty()) {
    throw ConfigError(c.origin + ": [height] source = \"lasers\" needs lasers_file: the file `gvs calibrate height "
                      "--out` wrote (or a camera.json with \"lasers\")");
  }
}

const std::array kRules{
    ConfigRule{"source", "`sim_ground` is `procedural` or `photo:FILE[:MM_PER_PIXEL]` with a scale of 0.01 .. 5 mm/px",
               check_sim_ground},
    ConfigRule{"can", "`status_period_ms` is a multiple of `period_ms`", check_status_period},
    ConfigRule{"exposure", "`min_pulse_us` <= `initial_us` <= `max_us`", check_exposure_order},
    ConfigRule{"libcamera", "`gain_min` <= `gain_max`", check_gain_order},
    ConfigRule{"light", "`driver = \"gpio\"` needs `led_line`, and `trigger_line` differs from it",
               check_gpio_lines},
    ConfigRule{"threads", "`prefault_stack_kb` is at most half of `stack_kb`", check_prefault_within_stack},
    ConfigRule{"height", "with `source = \"can\"`, the signal lies in 8 bytes, its ID fits its format, scale is not 0, and an interface is known",
               check_external_height},
    ConfigRule{"height", "with `source = \"lasers\"`, `lasers_file` names the beams' geometry", check_lasers_file},
};

/// Reads a key of a config that is not changed: the table's accessor takes a
/// mutable config so one function serves reading and writing.
ConfigField field_of(const ConfigKey& key, const DaemonConfig& c) {
  return key.field(const_cast<DaemonConfig&>(c));  // NOLINT(cppcoreguidelines-pro-type-const-cast)
}

}  // namespace

std::span<const ConfigSection> config_sections() { return kSections; }
std::span<const ConfigKey> config_keys() { return kKeys; }
std::span<const ConfigRule> config_rules() { return kRules; }

std::string key_path(const ConfigKey& key) { return std::string(key.section) + "." + std::string(key.name); }

std::string toml_value(const ConfigKey& key, const DaemonConfig& config) {
  return std::visit(
      [&](auto* p) -> std::string {
        using T = std::remove_pointer_t<decltype(p)>;
        if constexpr (std::is_same_v<T, std::string>) {
          std::string out = "\"";
          for (const char ch : *p) {
            if (ch == '"' || ch == '\\') out += '\\';
            out += ch;
          }
          return out + "\"";
        } else if constexpr (std::is_same_v<T, bool>) {
          return *p ? "true" : "false";
        } else if constexpr (std::is_same_v<T, double>) {
          std::string s = fmt::format("{}", *p);
          if (s.find_first_of(".en") == std::string::npos) s += ".0";  // TOML: a float stays a float
          return s;
        } else {
          if (key.hex) return fmt::format("0x{:X}", *p);
          return fmt::format("{}", *p);
        }
      },
      field_of(key, config));
}

std::string allowed_text(const ConfigKey& key) {
  const ConfigField f = field_of(key, DaemonConfig{});
  std::string out;
  if (std::holds_alternative<std::string*>(f)) {
    if (key.allowed == nullptr) return "text";
    out = "one of: ";
    bool first = true;
    for (const std::string& a : key.allowed()) {
      out.append(first ? "" : ", ").append(a);
      first = false;
    }
    return out;
  }
  if (std::holds_alternative<bool*>(f)) return "true or false";
  const bool integer = !std::holds_alternative<double*>(f);
  if (integer && key.hex) {
    out = fmt::format("0x{:X} .. 0x{:X}", static_cast<std::int64_t>(key.min), static_cast<std::int64_t>(key.max));
  } else if (integer) {
    out = fmt::format("{} .. {}", static_cast<std::int64_t>(key.min), static_cast<std::int64_t>(key.max));
  } else {
    out = fmt_num(key.min) + " .. " + fmt_num(key.max);
  }
  if (!key.unit.empty()) out.append(" ").append(key.unit);
  return out;
}

bool same_value(const ConfigKey& key, const DaemonConfig& a, const DaemonConfig& b) {
  return std::visit(
      [&](auto* pa) {
        using P = decltype(pa);
        return *pa == *std::get<P>(field_of(key, b));
      },
      field_of(key, a));
}

void copy_value(const ConfigKey& key, const DaemonConfig& from, DaemonConfig& to) {
  std::visit(
      [&](auto* dst) {
        using P = decltype(dst);
        *dst = *std::get<P>(field_of(key, from));
      },
      key.field(to));
}

}  // namespace gvs::daemon
