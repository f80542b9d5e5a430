// The vehicle-dynamics plausibility gate behind the estimator: an estimate
// that implies a change of speed or direction no car can make since the
// tracked velocity is held back (gvsd sends it with every Valid bit 0).
// Pure: no clocks, no I/O, no allocation, no exceptions; time comes from the
// estimates. docs/daemon.md, "Plausibility gate", states the rule.
#pragma once

#include <cstdint>

#include "gvs/core/estimate.hpp"

namespace gvs::daemon {

/// gvsd's [plausibility] keys.
struct PlausibilityLimits {
  double max_accel_mps2 = 29.4;         ///< 3 g: more than any car's tyres (and aero) give
  double speed_noise_mps = 0.3;         ///< measurement allowance at low speed
  double speed_noise_fraction = 0.05;   ///< measurement allowance as a share of the tracked speed
  double max_yaw_rate_dps = 300.0;      ///< the vehicle axes turn with the car at most this fast
  double direction_noise_deg = 3.0;     ///< measurement allowance of the direction
  double min_direction_speed_mps = 1.0; ///< below this the direction is not checked (it may turn at will)
  int reacquire_count = 5;              ///< this many rejected estimates in a row that agree: the car is there
  double track_timeout_ms = 500.0;      ///< a track older than this is dropped; the next estimate starts a new one

  bool operator==(const PlausibilityLimits&) const = default;
};

/// What the gate said about one estimate.
enum class Plausibility : std::uint8_t {
  unchecked,   ///< neither speed nor direction: nothing to check (goes out invalid anyway)
  started,     ///< no track (first estimate, or the track timed out): accepted, starts the track
  accepted,    ///< consistent with the track
  reacquired,  ///< rejected by the track, but the reacquire_count-th in a row that agree: becomes the track
  rejected,    ///< implausible: held back
};

[[nodiscard]] constexpr bool publishable(Plausibility p) noexcept { return p != Plausibility::rejected; }
[[nodiscard]] const char* to_string(Plausibility p) noexcept;

class PlausibilityGate {
 public:
  explicit PlausibilityGate(const PlausibilityLimits& limits = {}) noexcept : limits_(limits) {}

  /// Judges `e` (at e.t_ns) against the track and updates the track.
  Plausibility check(const core::VelocityEstimate& e) noexcept;
  /// New limits (reload); the track stays.
  void set_limits(const PlausibilityLimits& limits) noexcept { limits_ = limits; }
  /// Forgets the track.
  void reset() noexcept;

  /// The tracked velocity (for tests and the log).
  struct Track {
    bool has_speed = false;
    bool has_direction = false;
    double speed_mps = 0.0;
    double direction_deg = 0.0;
    std::int64_t speed_t_ns = 0;      ///< time of the estimate the speed came from
    std::int64_t direction_t_ns = 0;  ///< time of the estimate the direction came from
  };
  [[nodiscard]] bool tracking() const noexcept { return have_track_; }
  [[nodiscard]] const Track& track() const noexcept { return track_; }
  [[nodiscard]] const PlausibilityLimits& limits() const noexcept { return limits_; }

 private:
  /// Could the car go from `from` to the quantities of `e` at e.t_ns?
  [[nodiscard]] bool consistent(const Track& from, const core::VelocityEstimate& e) const noexcept;

  PlausibilityLimits limits_;
  bool have_track_ = false;
  Track track_;
  Track candidate_;  ///< the newest of the rejected estimates in a row that agree with each other
  int candidate_count_ = 0;
};

}  // namespace gvs::daemon
