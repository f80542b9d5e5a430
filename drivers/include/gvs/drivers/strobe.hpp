// The LED ring and the camera trigger: one frame's core::ExposurePlan turned
// into output edges (docs/hardware.md, "Light and trigger").
//
// Two drivers behind one interface:
//   gpio — libgpiod 1.6 lines timed from user space (clock_nanosleep to an
//          absolute time, then a short spin); every edge's achieved time is
//          recorded so the timing error can be reported (docs/hardware.md).
//   pwm  — the Linux PWM sysfs interface: the hardware times the pulse
//          (period = frame period, duty = pulse duration; single pulse only).
// Set-up (constructors, make_strobe_driver) throws std::runtime_error naming
// the chip, line or path and what to do; arm() and fire() never throw and
// never allocate: they run on gvsd's capture thread.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <string>

#include "gvs/core/frame.hpp"

namespace gvs::drivers {

/// [light] of gvsd.toml (see systemd/gvsd.toml).
struct StrobeConfig {
  std::string driver = "none";  ///< none | gpio | pwm
  // gpio
  std::string gpio_chip = "gpiochip0";  ///< name, number or /dev path (gpiod_chip_open_lookup)
  int led_line = -1;                    ///< offset of the LED ring's line on the chip
  int trigger_line = -1;                ///< -1: no external trigger output
  bool active_low = false;              ///< both lines are driven low when on
  std::string consumer = "gvsd";        ///< shown by gpioinfo as the lines' user
  double trigger_pulse_us = 10.0;       ///< width of the trigger pulse
  double spin_us = 500.0;               ///< busy-wait before each edge after the sleep (above the wake-up latency)
  double late_limit_us = 100.0;         ///< an edge later than this counts as late
  /// After each sleep, write every line's present level once (no edge)
  /// before spinning: the first set-value call after a sleep is several
  /// times slower than the next (measured, docs/hardware.md). Not in gvsd.toml.
  bool warm_up_write = true;
  // pwm
  std::string pwm_sysfs_root = "/sys/class/pwm";
  int pwm_chip = 0;
  int pwm_channel = 0;

  bool operator==(const StrobeConfig&) const = default;
};

enum class StrobeOutput : std::uint8_t { trigger, led };

/// One output edge of a frame: when it was due and when the line had it.
struct StrobeEdge {
  StrobeOutput output = StrobeOutput::led;
  bool on = false;               ///< logical level (active_low is applied by the line)
  std::int64_t target_ns = 0;    ///< CLOCK_MONOTONIC
  std::int64_t achieved_ns = 0;  ///< clock_gettime right after the set-value call returned
};

/// A frame's edges in time order: trigger on/off, then the LED's on/off per
/// pulse (no pulses: LED on for the whole exposure).
struct EdgeSchedule {
  static constexpr std::size_t kMaxEdges = 2 + 2 * core::ExposurePlan::kMaxPulses;
  std::array<StrobeEdge, kMaxEdges> edges{};
  std::size_t count = 0;
};

/// Edges for `plan` starting at `start_ns` (pure; no clocks). Pulses that
/// overlap are merged so the LED line never gets two "on" in a row.
EdgeSchedule make_edge_schedule(const core::ExposurePlan& plan, std::int64_t start_ns, bool with_trigger,
                                std::int64_t trigger_pulse_ns) noexcept;

/// A time the LED ring was on, from its achieved edges (CLOCK_MONOTONIC).
struct LitInterval {
  std::int64_t on_ns = 0;
  std::int64_t off_ns = 0;
};

/// The LED's on-intervals among `edges` (one fire()'s, in time order);
/// returns how many were written to `out` (at most out.size()).
std::size_t led_intervals(std::span<const StrobeEdge> edges, std::span<LitInterval> out) noexcept;

/// Where a frame did not get its light from its own source (a real camera
/// reports its shutter time only): the light that actually reached the
/// sensor, i.e. the parts of the `lit` intervals inside the exposure
/// [start_ns, start_ns + exposure_us), as the frame's pulses (relative to
/// the exposure start; pulse_count 0 when the LED was on for the whole
/// exposure, as the estimators read a continuous exposure). False when no
/// light fell in the exposure (the frame must not be measured) or more than
/// ExposurePlan::kMaxPulses pieces did.
bool light_in_exposure(std::span<const LitInterval> lit, std::int64_t start_ns, double exposure_us,
                       core::ExposurePlan& plan) noexcept;

/// What one fire() achieved.
struct FireReport {
  std::size_t edges = 0;        ///< edges driven
  std::size_t late_edges = 0;   ///< achieved - target > late_limit_us
  std::int64_t max_late_ns = 0; ///< largest achieved - target of this frame
  bool error = false;           ///< a set-value or sysfs write failed
};

class StrobeDriver {
 public:
  StrobeDriver() = default;
  StrobeDriver(const StrobeDriver&) = delete;
  StrobeDriver& operator=(const StrobeDriver&) = delete;
  virtual ~StrobeDriver() = default;

  /// "gpio gpiochip0 led 1 trigger 0 (active high, consumer gvsd)" — for the log.
  [[nodiscard]] virtual std::string describe() const = 0;
  /// The plan for the frames from now on, and their period. False when the
  /// driver cannot do the plan (e.g. pwm with two pulses) or a write failed.
  virtual bool arm(const core::ExposurePlan& plan, double frame_period_us) noexcept = 0;
  /// One frame: drives the armed plan's edges from `start_ns` (monotonic) and
  /// returns when the last is done. Hardware-timed drivers return at once.
  virtual FireReport fire(std::int64_t start_ns) noexcept = 0;
  /// The edges of the last fire() with their achieved times.
  [[nodiscard]] virtual std::span<const StrobeEdge> last_edges() const noexcept = 0;
  /// Hardware-timed drivers have no per-frame edges to report.
  [[nodiscard]] virtual bool hardware_timed() const noexcept = 0;
};

/// The driver `config.driver` names; nullptr for "none". Throws
/// std::runtime_error (unknown driver, chip or line that cannot be had).
std::unique_ptr<StrobeDriver> make_strobe_driver(const StrobeConfig& config);

}  // namespace gvs::drivers
