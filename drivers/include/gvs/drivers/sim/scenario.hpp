// Driving scenarios for the simulator and the car's pose integrated from them.
//
// A scenario gives the velocity of the *sensor* over the ground in vehicle
// axes (ISO 8855: x forward, y left, yaw rate CCW from above) as a function of
// time. The trajectory integrates it into a world pose (RK4 at 50 us, cubic
// Hermite in between), so the camera sees exactly the motion the truth says.
// A scenario may also move the body: the camera's height above the ground
// and the body's pitch and roll as functions of time (docs/simulator.md,
// "Body motion").
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace gvs::drivers::sim {

/// Velocity of the sensor over the ground, vehicle axes.
struct BodyMotion {
  double vx_mps = 0.0;        ///< forward
  double vy_mps = 0.0;        ///< left
  double yaw_rate_dps = 0.0;  ///< CCW from above
};

/// The body's height and attitude at the sensor, relative to the ground
/// plane (shared/spec/dataset-format.md, truth.csv: height_mm, pitch_deg,
/// roll_deg). All zero: the nominal height, level.
struct BodyPose {
  /// Change of the camera's height (optical centre to the ground along the
  /// vehicle's z axis) from its nominal height; positive = higher.
  double heave_mm = 0.0;
  double pitch_deg = 0.0;  ///< ISO 8855: positive = nose down
  double roll_deg = 0.0;   ///< ISO 8855: positive = right side down
};

/// A driving scenario: body motion as a function of time since its start.
/// `motion` must be defined (and should be continuous) for every t >= 0; the
/// built-in ones hold their final state after `length_s`.
struct Scenario {
  std::string name;
  double length_s = 1.0;  ///< default run length
  std::function<BodyMotion(double t_s)> motion;
  /// Height and attitude of the body, continuous for every t >= 0; empty:
  /// nominal height and level all the time (the truth then has no
  /// height_mm, pitch_deg, roll_deg columns). The velocity of `motion` is
  /// that of the ground point on the camera's axis (the image centre).
  std::function<BodyPose(double t_s)> body = {};
};

/// Builds a built-in scenario (const, sine, accel, brake, skidpad, crawl,
/// stop, spin). Throws std::invalid_argument naming the scenario and the known ones.
Scenario make_scenario(const std::string& name);

/// Names of the built-in scenarios.
std::vector<std::string> builtin_scenario_names();

/// Body motion laid over any scenario (docs/simulator.md, "Body motion"):
///  - "flat": none (nominal height, level; the scenario as it is);
///  - "heave": the height only, +-5 mm at 1.3, 2.9 and 4.7 Hz (sum of sines);
///  - "ride": "heave" plus pitch and roll following the scenario's own
///    accelerations (1 deg/g braking/accelerating, limited to 1.5 deg;
///    0.75 deg/g in corners, limited to 1 deg) and a kerb strike every 4 s
///    from 1.5 s (up 10 mm in 50 ms, down again in 150 ms, 0.5 deg of roll).
/// Throws std::invalid_argument naming the body and the known ones.
Scenario with_body_motion(Scenario scenario, const std::string& body);

/// Names of the body motions: flat, heave, ride.
std::vector<std::string> body_motion_names();

/// Constant body velocity for `length_s` seconds (tests, calibration runs).
Scenario constant_motion_scenario(double vx_mps, double vy_mps, double yaw_rate_dps = 0.0,
                                  double length_s = 2.0);

/// Pose of the sensor in the world (ground) frame: position in metres, yaw in
/// radians (CCW from above, 0 = vehicle x along world X).
struct Pose {
  double x_m = 0.0;
  double y_m = 0.0;
  double yaw_rad = 0.0;
};

/// The scenario integrated into world poses. With `loop`, the scenario
/// restarts every `period_s` while the pose keeps going (the car drives on).
class Trajectory {
 public:
  Trajectory(Scenario scenario, double period_s, bool loop);

  [[nodiscard]] Pose pose(double t_s) const;
  [[nodiscard]] BodyMotion motion(double t_s) const;
  /// The scenario's body pose at t (all zero without body motion).
  [[nodiscard]] BodyPose body(double t_s) const;
  [[nodiscard]] bool has_body_motion() const { return static_cast<bool>(scenario_.body); }
  [[nodiscard]] double period_s() const { return period_s_; }
  [[nodiscard]] const Scenario& scenario() const { return scenario_; }

  /// RK4 step of the pose table: 50 us, longer for runs over 50 s (at most
  /// 1e6 table entries).
  [[nodiscard]] double step_s() const { return step_s_; }

 private:
  [[nodiscard]] Pose pose_in_period(double tau_s) const;
  [[nodiscard]] Pose loop_base(std::int64_t n) const;

  Scenario scenario_;
  double period_s_;
  bool loop_;
  double step_s_;
  std::vector<Pose> table_;        ///< pose every step_s() from 0 to period (+ margin)
  mutable std::vector<Pose> bases_;  ///< pose at the start of pass n (loop)
};

}  // namespace gvs::drivers::sim
