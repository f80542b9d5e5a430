// Body motion laid over a driving scenario: the camera's height and the
// body's pitch and roll as functions of time (docs/simulator.md, "Body
// motion"). The figures are those of a Formula Student car with stiff
// springs and aero (issue 21): a few mm of heave at 1-5 Hz, pitch up to about
// 1.5 deg under braking and acceleration, roll up to about 1 deg in corners,
// and a kerb strike of 10 mm in 50 ms.
#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "gvs/drivers/sim/scenario.hpp"

namespace gvs::drivers::sim {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kG = 9.80665;  ///< standard gravity, m/s^2

/// Heave: three sines across the band of body and wheel-hop-free road input
/// (1-5 Hz); the amplitudes add up to 5 mm, so the height stays within
/// +-5 mm of nominal. Incommensurate frequencies: no short repeat.
double heave_mm(double t) {
  return 2.5 * std::sin(2.0 * kPi * 1.3 * t) + 1.5 * std::sin(2.0 * kPi * 2.9 * t + 1.1) +
         1.0 * std::sin(2.0 * kPi * 4.7 * t + 2.3);
}

/// C2 smooth step from 0 (x <= 0) to 1 (x >= 1): x^3 (10 - 15x + 6x^2).
double smooth(double x) {
  x = std::clamp(x, 0.0, 1.0);
  return x * x * x * (10.0 - 15.0 * x + 6.0 * x * x);
}

/// Kerb strike shape in [0, 1]: up in 50 ms (a wheel climbs a kerb of ~25 mm
/// at racing speed; the sprung mass follows by about 10 mm), down in 150 ms
/// (the spring and damper bring it back). One every 4 s from 1.5 s.
constexpr double kKerbFirstS = 1.5;
constexpr double kKerbEveryS = 4.0;
constexpr double kKerbRiseS = 0.050;
constexpr double kKerbFallS = 0.150;
double kerb(double t) {
  if (t < kKerbFirstS) return 0.0;
  const double tau = std::fmod(t - kKerbFirstS, kKerbEveryS);
  if (tau < kKerbRiseS) return smooth(tau / kKerbRiseS);
  return 1.0 - smooth((tau - kKerbRiseS) / kKerbFallS);
}
constexpr double kKerbHeaveMm = 10.0;
constexpr double kKerbRollDeg = 0.5;  ///< the kerb lifts the left wheels: right side down

/// Quasi-static attitude from the acceleration (the steady-state pitch and
/// roll gradients of a stiff FS car; Milliken & Milliken, "Race Car Vehicle
/// Dynamics", ch. 18): no suspension lag, the heave's sines stand in for the
/// dynamics. A soft limit (L tanh(x / L)) keeps the scenarios' harsher
/// transitions (const: up to 8 g in 0.25 s) at the limits the issue names.
constexpr double kPitchDegPerG = 1.0;
constexpr double kPitchLimitDeg = 1.5;
constexpr double kRollDegPerG = 0.75;
constexpr double kRollLimitDeg = 1.0;
double soft_limit(double x, double limit) { return limit * std::tanh(x / limit); }

/// Acceleration of the sensor in vehicle axes, m/s^2: a = dv/dt + omega x v
/// (ISO 8855), dv/dt by a central difference over 2 ms.
void acceleration(const Scenario& s, double t, double& ax, double& ay) {
  constexpr double kDt = 0.002;
  const double t0 = std::max(0.0, t - kDt);
  const double t1 = t0 + 2.0 * kDt;
  const BodyMotion a = s.motion(t0);
  const BodyMotion b = s.motion(t1);
  const BodyMotion m = s.motion(t);
  const double r = m.yaw_rate_dps * kPi / 180.0;
  ax = (b.vx_mps - a.vx_mps) / (t1 - t0) - r * m.vy_mps;
  ay = (b.vy_mps - a.vy_mps) / (t1 - t0) + r * m.vx_mps;
}

}  // namespace

std::vector<std::string> body_motion_names() { return {"flat", "heave", "ride"}; }

Scenario with_body_motion(Scenario scenario, const std::string& body) {
  if (body == "flat") return scenario;
  if (body == "heave") {
    scenario.body = [](double t) { return BodyPose{heave_mm(t), 0.0, 0.0}; };
    return scenario;
  }
  if (body == "ride") {
    // The body function reads the scenario's own motion (a copy: the
    // scenario is moved into the trajectory afterwards).
    scenario.body = [s = scenario](double t) {
      double ax = 0.0;
      double ay = 0.0;
      acceleration(s, t, ax, ay);
      const double k = kerb(t);
      // Braking (ax < 0) pitches the nose down (positive); a left turn
      // (ay > 0) rolls the body to the right (positive).
      return BodyPose{heave_mm(t) + kKerbHeaveMm * k, soft_limit(-kPitchDegPerG * ax / kG, kPitchLimitDeg),
                      soft_limit(kRollDegPerG * ay / kG, kRollLimitDeg) + kKerbRollDeg * k};
    };
    return scenario;
  }
  std::string known;
  for (const auto& n : body_motion_names()) known += (known.empty() ? "" : ", ") + n;
  throw std::invalid_argument("simulator: unknown body motion '" + body + "' (known: " + known + ")");
}

}  // namespace gvs::drivers::sim
