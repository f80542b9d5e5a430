// Scenarios and the trajectory: every built-in scenario runs, has the
// advertised motion, and the integrated pose is accurate.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

#include "gvs/drivers/simulator.hpp"

namespace gvs::drivers::sim {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

double speed(const BodyMotion& m) { return std::hypot(m.vx_mps, m.vy_mps); }
double direction(const BodyMotion& m) { return std::atan2(m.vy_mps, m.vx_mps) / kDeg; }

TEST(SimScenario, EveryBuiltInScenarioRendersFramesWithTruth) {
  ASSERT_EQ(scenario_names().size(), 8U);
  for (const std::string& name : scenario_names()) {
    SimulatorConfig c;
    c.scenario = name;
    Simulator sim(c);
    const Scenario s = make_scenario(name);
    EXPECT_GE(s.length_s, 3.0) << name;
    EXPECT_LE(s.length_s, 12.0) << name;
    EXPECT_EQ(sim.frame_count(), static_cast<std::size_t>(std::floor(s.length_s * 60.0 + 1e-9))) << name;
    EXPECT_EQ(sim.config().scenario, name);
    SimFrame f;
    ASSERT_TRUE(sim.next(f)) << name;
    EXPECT_EQ(f.gray.type(), CV_8UC1);
    EXPECT_EQ(f.gray.rows, 384);
    EXPECT_EQ(f.gray.cols, 512);
    EXPECT_EQ(f.record.index, 0);
    EXPECT_EQ(f.record.t_ns, 0);
    EXPECT_EQ(f.truth.t_ns, 1500000);
    ASSERT_TRUE(sim.next(f));
    EXPECT_EQ(f.record.t_ns, 16666667);
  }
}

TEST(SimScenario, UnknownScenarioIsRejectedWithTheKnownNames) {
  SimulatorConfig c;
  c.scenario = "drift";
  try {
    Simulator sim(c);
    FAIL() << "no exception";
  } catch (const std::invalid_argument& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("drift"), std::string::npos);
    EXPECT_NE(msg.find("skidpad"), std::string::npos);
  }
}

TEST(SimScenario, BadSettingsAreRejected) {
  SimulatorConfig c;
  c.fps = 0.0;
  EXPECT_THROW(Simulator{c}, std::invalid_argument);
  c = SimulatorConfig{};
  c.exposure_us = 20000.0;
  EXPECT_THROW(Simulator{c}, std::invalid_argument);
  c = SimulatorConfig{};
  c.camera.mm_per_px = 0.0;
  EXPECT_THROW(Simulator{c}, std::invalid_argument);
}

TEST(SimScenario, ConstStepsThroughItsSpeedsAtTenDegrees) {
  const Scenario s = make_scenario("const");
  const double kmh[] = {1, 2, 5, 10, 20, 40, 70, 100, 140};
  for (int i = 0; i < 9; ++i) {
    const BodyMotion m = s.motion(i + 0.6);
    EXPECT_NEAR(speed(m) * 3.6, kmh[i], 1e-9);
    EXPECT_NEAR(direction(m), 10.0, 1e-9);
    EXPECT_EQ(m.yaw_rate_dps, 0.0);
  }
}

TEST(SimScenario, SineSwingsTheDirectionAt60Kmh) {
  const Scenario s = make_scenario("sine");
  EXPECT_NEAR(speed(s.motion(0.3)) * 3.6, 60.0, 1e-9);
  EXPECT_NEAR(direction(s.motion(0.5)), 8.0, 1e-9);  // sin(2 pi 0.5 * 0.5) = 1
  EXPECT_NEAR(direction(s.motion(1.5)), -8.0, 1e-9);
}

TEST(SimScenario, AccelGoesFrom0To140KmhIn6s) {
  const Scenario s = make_scenario("accel");
  EXPECT_EQ(speed(s.motion(0.2)), 0.0);
  EXPECT_NEAR(speed(s.motion(6.5)) * 3.6, 140.0, 1e-9);
  double prev = 0.0;
  for (double t = 0.5; t < 6.5; t += 0.1) {
    EXPECT_GE(speed(s.motion(t)), prev);
    prev = speed(s.motion(t));
  }
}

TEST(SimScenario, SkidpadDrivesTheCircleOfRadius9125) {
  const Scenario s = make_scenario("skidpad");
  const BodyMotion m = s.motion(4.0);
  EXPECT_NEAR(speed(m), 12.0, 1e-9);
  EXPECT_NEAR(m.yaw_rate_dps * kDeg, 12.0 / 9.125, 1e-9);
  EXPECT_LT(direction(m), -1.0);  // sideslip
  // The integrated path: the centre of curvature stays put, 9.125 m away.
  Trajectory traj(s, s.length_s, false);
  auto centre = [&](double t) {
    const Pose p = traj.pose(t);
    const BodyMotion v = traj.motion(t);
    const double heading = p.yaw_rad + std::atan2(v.vy_mps, v.vx_mps);
    return std::pair{p.x_m - 9.125 * std::sin(heading), p.y_m + 9.125 * std::cos(heading)};
  };
  const auto c0 = centre(2.0);
  for (double t = 2.5; t <= 8.0; t += 0.5) {
    const auto c = centre(t);
    EXPECT_NEAR(c.first, c0.first, 1e-4) << "t = " << t;
    EXPECT_NEAR(c.second, c0.second, 1e-4) << "t = " << t;
  }
}

TEST(SimScenario, CrawlStaysSlowAndChangesDirection) {
  const Scenario s = make_scenario("crawl");
  double lo = 1e9, hi = 0.0, dmin = 1e9, dmax = -1e9;
  for (double t = 0.0; t <= s.length_s; t += 0.01) {
    const BodyMotion m = s.motion(t);
    lo = std::min(lo, speed(m));
    hi = std::max(hi, speed(m));
    dmin = std::min(dmin, direction(m));
    dmax = std::max(dmax, direction(m));
  }
  EXPECT_GE(lo, 0.1 - 1e-9);
  EXPECT_LE(hi, 4.0 + 1e-9);
  EXPECT_GT(hi, 3.9);
  EXPECT_GT(dmax - dmin, 180.0);
}

TEST(SimScenario, StopStandsThenPullsAway) {
  SimulatorConfig c;
  c.scenario = "stop";
  Simulator sim(c);
  SimFrame f;
  sim.render(30, sim.exposure(), f);  // 0.5 s
  EXPECT_EQ(f.truth.speed_mps, 0.0);
  EXPECT_FALSE(f.truth.direction_deg.has_value());
  sim.render(300, sim.exposure(), f);  // 5 s
  EXPECT_NEAR(f.truth.speed_mps, 5.0, 1e-6);
  ASSERT_TRUE(f.truth.direction_deg.has_value());
}

TEST(SimScenario, BrakeStopsFrom100KmhAtUpTo2g) {
  const Scenario s = make_scenario("brake");
  EXPECT_NEAR(speed(s.motion(0.4)), 100.0 / 3.6, 1e-9);
  EXPECT_EQ(speed(s.motion(3.05)), 0.0);
  EXPECT_EQ(speed(s.motion(3.9)), 0.0);
  double peak = 0.0;
  for (double t = 0.0; t < 4.0; t += 0.01) {
    const double decel = (speed(s.motion(t)) - speed(s.motion(t + 0.01))) / 0.01;
    ASSERT_GE(decel, -1e-9) << t;  // never speeds up
    peak = std::max(peak, decel);
    if (speed(s.motion(t)) > 0.01) {
      EXPECT_NEAR(direction(s.motion(t)), 0.0, 1e-12);
    }
  }
  EXPECT_NEAR(peak, 100.0 / 3.6 * 1.875 / 2.5, 0.05);  // 20.8 m/s^2
}

TEST(SimScenario, SpinTurnsThrough180DegreesAndEndsGoingBackwards) {
  const Scenario s = make_scenario("spin");
  Trajectory traj(s, s.length_s, false);
  EXPECT_NEAR(traj.pose(s.length_s).yaw_rad, std::numbers::pi, 1e-6);
  double dmin = 0.0;
  for (double t = 0.0; t <= s.length_s; t += 0.01) dmin = std::min(dmin, direction(s.motion(t)));
  EXPECT_LT(dmin, -175.0);
  const BodyMotion end = s.motion(4.5);
  EXPECT_LT(end.vx_mps, 0.0);  // backwards
  EXPECT_GT(speed(end), 1.0);
  // World velocity keeps its direction while the car rotates (a slide).
  for (double t = 0.5; t < 4.5; t += 0.25) {
    const Pose p = traj.pose(t);
    const BodyMotion m = traj.motion(t);
    const double world_dir = p.yaw_rad + std::atan2(m.vy_mps, m.vx_mps);
    EXPECT_NEAR(std::remainder(world_dir, 2 * std::numbers::pi), 0.0, 1e-6) << "t = " << t;
  }
}

TEST(SimScenario, TrajectoryIntegratesConstantMotionExactly) {
  // 3 m/s forward, 1 m/s left, 40 deg/s: a circle; compare with the closed form.
  const double w = 40.0 * kDeg;
  Trajectory traj(constant_motion_scenario(3.0, 1.0, 40.0, 5.0), 5.0, false);
  for (double t : {0.0, 0.37, 1.0, 2.71828, 4.99}) {
    const Pose p = traj.pose(t);
    // x + i y = (vx + i vy) (e^{i w t} - 1) / (i w)
    const double c = std::cos(w * t) - 1.0;
    const double s = std::sin(w * t);
    const double ex = (3.0 * s + 1.0 * c) / w;
    const double ey = (1.0 * s - 3.0 * c) / w;
    EXPECT_NEAR(p.x_m, ex, 1e-9) << "t = " << t;
    EXPECT_NEAR(p.y_m, ey, 1e-9) << "t = " << t;
    EXPECT_NEAR(p.yaw_rad, w * t, 1e-9);
  }
}

TEST(SimScenario, LoopRestartsTheScenarioAndTheCarDrivesOn) {
  SimulatorConfig c;
  c.scenario = "stop";
  c.seconds = 0.5;  // 30 frames per pass
  c.loop = true;
  Simulator sim(c);
  ASSERT_EQ(sim.frame_count(), 30U);
  SimFrame f;
  for (int i = 0; i < 65; ++i) ASSERT_TRUE(sim.next(f));
  EXPECT_EQ(f.record.index, 64);
  c.loop = false;
  Simulator once(c);
  int n = 0;
  while (once.next(f)) ++n;
  EXPECT_EQ(n, 30);
  // A looping trajectory keeps going: poses continue across the restart.
  Trajectory traj(constant_motion_scenario(2.0, 0.0, 10.0, 1.0), 1.0, true);
  const Pose before = traj.pose(0.999999);
  const Pose after = traj.pose(1.000001);
  EXPECT_NEAR(after.x_m - before.x_m, 2.0 * 2e-6 * std::cos(before.yaw_rad), 1e-8);
  EXPECT_NEAR(after.yaw_rad - before.yaw_rad, 10.0 * kDeg * 2e-6, 1e-9);
  EXPECT_NEAR(traj.pose(2.5).yaw_rad, 25.0 * kDeg, 1e-9);
}

}  // namespace
}  // namespace gvs::drivers::sim
