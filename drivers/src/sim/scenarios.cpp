// The built-in driving scenarios (docs/simulator.md, "Scenarios").
#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>
#include <vector>

#include "gvs/drivers/sim/scenario.hpp"

namespace gvs::drivers::sim {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kDeg = kPi / 180.0;

/// C2 smooth step from 0 (x <= 0) to 1 (x >= 1): x^3 (10 - 15x + 6x^2).
double smooth(double x) {
  x = std::clamp(x, 0.0, 1.0);
  return x * x * x * (10.0 - 15.0 * x + 6.0 * x * x);
}
/// Derivative of smooth() with respect to x.
double smooth_slope(double x) {
  if (x <= 0.0 || x >= 1.0) return 0.0;
  return 30.0 * x * x * (1.0 - x) * (1.0 - x);
}

BodyMotion polar(double speed_mps, double direction_deg, double yaw_rate_dps = 0.0) {
  return {speed_mps * std::cos(direction_deg * kDeg), speed_mps * std::sin(direction_deg * kDeg),
          yaw_rate_dps};
}

/// Speeds 1 ... 140 km/h at a fixed direction of 10 deg, 1 s each, 0.25 s transitions.
Scenario const_scenario() {
  return {"const", 9.0, [](double t) {
            static constexpr std::array<double, 9> kKmh{1, 2, 5, 10, 20, 40, 70, 100, 140};
            const double step = std::clamp(std::floor(t), 0.0, 8.0);
            const auto i = static_cast<std::size_t>(step);
            double kmh = kKmh[i];
            if (i > 0) kmh = kKmh[i - 1] + (kKmh[i] - kKmh[i - 1]) * smooth((t - step) / 0.25);
            return polar(kmh / 3.6, 10.0);
          }};
}

/// 60 km/h, direction 8 sin(2 pi 0.5 t) deg.
Scenario sine_scenario() {
  return {"sine", 10.0,
          [](double t) { return polar(60.0 / 3.6, 8.0 * std::sin(2.0 * kPi * 0.5 * t)); }};
}

/// Standing 0.5 s, 0 -> 140 km/h in 6 s (smooth, peak 12 m/s^2), 1 s at 140 km/h.
Scenario accel_scenario() {
  return {"accel", 7.5, [](double t) { return polar(140.0 / 3.6 * smooth((t - 0.5) / 6.0), 0.0); }};
}

/// Skidpad circle: radius 9.125 m at 12 m/s, turning left. Yaw rate and
/// sideslip (-3 deg: nose inside the circle) build up over the first 1.5 s.
Scenario skidpad_scenario() {
  return {"skidpad", 8.0, [](double t) {
            constexpr double kSpeed = 12.0;
            constexpr double kRadius = 9.125;
            const double s = smooth(t / 1.5);
            // Path curvature of the sensor = (yaw rate + d(beta)/dt) / v; in the
            // steady state yaw rate = v / R. The build-up is a clothoid-like entry.
            const double beta_deg = -3.0 * s;
            const double yaw_rate_dps = (kSpeed / kRadius) / kDeg * s;
            return polar(kSpeed, beta_deg, yaw_rate_dps);
          }};
}

/// Crawling 0.1 - 4 m/s with direction changes (including reversing) and a
/// little yaw.
Scenario crawl_scenario() {
  return {"crawl", 10.0, [](double t) {
            // (speed m/s, direction deg unwrapped), 1.25 s per waypoint, 0.5 s blends.
            static constexpr std::array<std::array<double, 2>, 9> kWay{{{0.1, 0.0},
                                                                        {0.3, 20.0},
                                                                        {1.0, -30.0},
                                                                        {2.0, 60.0},
                                                                        {4.0, 0.0},
                                                                        {0.5, 120.0},
                                                                        {1.5, 180.0},
                                                                        {0.2, 270.0},
                                                                        {1.0, 360.0}}};
            constexpr double kHold = 1.25;
            const double step = std::clamp(std::floor(t / kHold), 0.0, 8.0);
            const auto i = static_cast<std::size_t>(step);
            double speed = kWay[i][0];
            double dir = kWay[i][1];
            if (i > 0) {
              const double b = smooth((t - step * kHold) / 0.5);
              speed = kWay[i - 1][0] + (kWay[i][0] - kWay[i - 1][0]) * b;
              dir = kWay[i - 1][1] + (kWay[i][1] - kWay[i - 1][1]) * b;
            }
            return polar(speed, dir, 8.0 * std::sin(2.0 * kPi * 0.15 * t));
          }};
}

/// Standing still 2 s, then pulling away to 5 m/s within 2.5 s.
Scenario stop_scenario() {
  return {"stop", 6.0, [](double t) { return polar(5.0 * smooth((t - 2.0) / 2.5), 0.0); }};
}

/// 100 km/h for 0.5 s, braking to a standstill within 2.5 s (smooth: the
/// deceleration peaks at 20.8 m/s^2, 2.1 g, at 1.75 s, as an FS car with
/// aero and slicks brakes from that speed), standing for the last second.
Scenario brake_scenario() {
  return {"brake", 4.0, [](double t) {
            // (max: smooth() may round to a hair above 1, which would be a backwards crawl.)
            return polar(100.0 / 3.6 * std::max(0.0, 1.0 - smooth((t - 0.5) / 2.5)), 0.0);
          }};
}

/// Sliding at 15 m/s (decelerating at 4.5 m/s^2 once the spin starts) while
/// the car rotates through 180 deg CCW between 1 s and 3 s; the world velocity
/// keeps its direction, so in vehicle axes the direction sweeps 0 -> -180 deg
/// (travelling backwards at the end).
Scenario spin_scenario() {
  return {"spin", 5.0, [](double t) {
            const double x = (t - 1.0) / 2.0;
            const double yaw = kPi * smooth(x);
            const double yaw_rate = kPi * smooth_slope(x) / 2.0;
            const double speed = std::max(15.0 - 4.5 * std::clamp(t - 1.0, 0.0, 3.0), 0.0);
            return BodyMotion{speed * std::cos(yaw), -speed * std::sin(yaw), yaw_rate / kDeg};
          }};
}

}  // namespace

std::vector<std::string> builtin_scenario_names() {
  return {"const", "sine", "accel", "brake", "skidpad", "crawl", "stop", "spin"};
}

Scenario make_scenario(const std::string& name) {
  if (name == "const") return const_scenario();
  if (name == "sine") return sine_scenario();
  if (name == "accel") return accel_scenario();
  if (name == "brake") return brake_scenario();
  if (name == "skidpad") return skidpad_scenario();
  if (name == "crawl") return crawl_scenario();
  if (name == "stop") return stop_scenario();
  if (name == "spin") return spin_scenario();
  std::string known;
  for (const auto& n : builtin_scenario_names()) known += (known.empty() ? "" : ", ") + n;
  throw std::invalid_argument("simulator: unknown scenario '" + name + "' (known: " + known + ")");
}

Scenario constant_motion_scenario(double vx_mps, double vy_mps, double yaw_rate_dps,
                                  double length_s) {
  return {"constant", length_s,
          [=](double) { return BodyMotion{vx_mps, vy_mps, yaw_rate_dps}; }};
}

}  // namespace gvs::drivers::sim
