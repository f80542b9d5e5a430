#include "gvs/daemon/plausibility_gate.hpp"

#include <algorithm>
#include <cmath>

namespace gvs::daemon {

namespace {

constexpr double kDegPerRad = 57.29577951308232;

bool usable_speed(const core::VelocityEstimate& e) { return e.has_speed && std::isfinite(e.speed_mps); }
bool usable_direction(const core::VelocityEstimate& e) {
  return e.has_direction && std::isfinite(e.direction_deg);
}

double seconds_between(std::int64_t from_ns, std::int64_t to_ns) {
  return std::max(0.0, static_cast<double>(to_ns - from_ns) * 1e-9);
}

/// |a - b| on the circle, 0..180 deg.
double angle_between_deg(double a, double b) {
  const double d = std::fmod(std::fabs(a - b), 360.0);
  return d > 180.0 ? 360.0 - d : d;
}

/// Takes the quantities `e` has into `t`; a speed without a direction
/// (standstill) forgets the direction: the car may leave in any.
void take(PlausibilityGate::Track& t, const core::VelocityEstimate& e) {
  if (usable_speed(e)) {
    t.has_speed = true;
    t.speed_mps = e.speed_mps;
    t.speed_t_ns = e.t_ns;
    if (!usable_direction(e)) t.has_direction = false;
  }
  if (usable_direction(e)) {
    t.has_direction = true;
    t.direction_deg = e.direction_deg;
    t.direction_t_ns = e.t_ns;
  }
}

PlausibilityGate::Track track_of(const core::VelocityEstimate& e) {
  PlausibilityGate::Track t;
  take(t, e);
  return t;
}

}  // namespace

const char* to_string(Plausibility p) noexcept {
  switch (p) {
    case Plausibility::unchecked: return "unchecked";
    case Plausibility::started: return "started";
    case Plausibility::accepted: return "accepted";
    case Plausibility::reacquired: return "reacquired";
    case Plausibility::rejected: return "rejected";
  }
  return "?";
}

void PlausibilityGate::reset() noexcept {
  have_track_ = false;
  track_ = {};
  candidate_ = {};
  candidate_count_ = 0;
}

bool PlausibilityGate::consistent(const Track& from, const core::VelocityEstimate& e) const noexcept {
  const PlausibilityLimits& l = limits_;
  // Speed: |d|v|/dt| <= |a| for any motion, turning or not, so
  // |v_new - v_track| <= a_max * dt + max(noise, fraction * v_track).
  const double dt_speed_s = seconds_between(from.speed_t_ns, e.t_ns);
  const double speed_allowance_mps =
      l.max_accel_mps2 * dt_speed_s + std::max(l.speed_noise_mps, l.speed_noise_fraction * from.speed_mps);
  if (from.has_speed && usable_speed(e) && std::fabs(e.speed_mps - from.speed_mps) > speed_allowance_mps) return false;

  // Direction in vehicle axes turns with the yaw rate plus the course rate
  // a_lat / v (kinematics of a point on a rigid body), so over dt it can move
  // by (max_yaw_rate + a_max / v_low) * dt, v_low the lowest speed the car
  // can have had since the track. Below min_direction_speed_mps that bound
  // is meaningless (a car may turn its velocity at will near standstill).
  if (from.has_direction && from.has_speed && usable_direction(e)) {
    const double v_low_mps = from.speed_mps - speed_allowance_mps;
    if (v_low_mps >= l.min_direction_speed_mps) {
      const double dt_dir_s = seconds_between(from.direction_t_ns, e.t_ns);
      const double turn_rate_dps = l.max_yaw_rate_dps + l.max_accel_mps2 / v_low_mps * kDegPerRad;
      const double allowed_deg = turn_rate_dps * dt_dir_s + l.direction_noise_deg;
      if (angle_between_deg(e.direction_deg, from.direction_deg) > allowed_deg) return false;
    }
  }
  return true;
}

Plausibility PlausibilityGate::check(const core::VelocityEstimate& e) noexcept {
  if (!usable_speed(e) && !usable_direction(e)) return Plausibility::unchecked;

  const std::int64_t newest_t_ns = std::max(track_.has_speed ? track_.speed_t_ns : INT64_MIN,
                                            track_.has_direction ? track_.direction_t_ns : INT64_MIN);
  const bool timed_out =
      have_track_ && static_cast<double>(e.t_ns - newest_t_ns) * 1e-6 > limits_.track_timeout_ms;
  if (!have_track_ || timed_out) {
    track_ = track_of(e);
    have_track_ = true;
    candidate_count_ = 0;
    return Plausibility::started;
  }
  if (consistent(track_, e)) {
    take(track_, e);
    candidate_count_ = 0;
    return Plausibility::accepted;
  }
  // Held back. If the rejected estimates agree with each other, the car may
  // really be there (the track latched on an outlier): after
  // reacquire_count of them in a row the newest becomes the track.
  if (candidate_count_ > 0 && consistent(candidate_, e)) {
    take(candidate_, e);
    ++candidate_count_;
  } else {
    candidate_ = track_of(e);
    candidate_count_ = 1;
  }
  if (candidate_count_ >= limits_.reacquire_count) {
    track_ = candidate_;
    candidate_count_ = 0;
    return Plausibility::reacquired;
  }
  return Plausibility::rejected;
}

}  // namespace gvs::daemon
