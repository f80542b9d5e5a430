// Integrates a scenario's body motion into world poses (RK4, 50 us table,
// cubic Hermite interpolation using the exact velocities at the knots).
#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <utility>

#include "gvs/drivers/sim/scenario.hpp"

namespace gvs::drivers::sim {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

struct PoseRate {
  double dx = 0.0;
  double dy = 0.0;
  double dyaw = 0.0;
};

/// World-frame rate of the pose: d(x,y)/dt = R(yaw) (vx, vy), d(yaw)/dt = r.
PoseRate rate(const BodyMotion& m, double yaw) {
  const double c = std::cos(yaw);
  const double s = std::sin(yaw);
  return {c * m.vx_mps - s * m.vy_mps, s * m.vx_mps + c * m.vy_mps, m.yaw_rate_dps * kDeg};
}

Pose compose(const Pose& base, const Pose& rel) {
  const double c = std::cos(base.yaw_rad);
  const double s = std::sin(base.yaw_rad);
  return {base.x_m + c * rel.x_m - s * rel.y_m, base.y_m + s * rel.x_m + c * rel.y_m,
          base.yaw_rad + rel.yaw_rad};
}

}  // namespace

Trajectory::Trajectory(Scenario scenario, double period_s, bool loop)
    : scenario_(std::move(scenario)),
      period_s_(period_s),
      loop_(loop),
      step_s_(std::max(50e-6, (period_s + 0.1) / 1e6)) {
  if (!scenario_.motion) throw std::invalid_argument("simulator: scenario '" + scenario_.name + "' has no motion function");
  if (!(period_s_ > 0.0) || period_s_ > 24.0 * 3600.0)
    throw std::invalid_argument("simulator: run length must be in (0, 86400] s");
  // The table covers one period plus a margin for the last exposure.
  const auto n = static_cast<std::size_t>(std::ceil((period_s_ + 0.1) / step_s_)) + 2;
  table_.resize(n);
  Pose p;
  const auto& f = scenario_.motion;
  for (std::size_t i = 0; i < n; ++i) {
    table_[i] = p;
    const double t = static_cast<double>(i) * step_s_;
    const double h = step_s_;
    const PoseRate k1 = rate(f(t), p.yaw_rad);
    const PoseRate k2 = rate(f(t + h / 2), p.yaw_rad + h / 2 * k1.dyaw);
    const PoseRate k3 = rate(f(t + h / 2), p.yaw_rad + h / 2 * k2.dyaw);
    const PoseRate k4 = rate(f(t + h), p.yaw_rad + h * k3.dyaw);
    p.x_m += h / 6 * (k1.dx + 2 * k2.dx + 2 * k3.dx + k4.dx);
    p.y_m += h / 6 * (k1.dy + 2 * k2.dy + 2 * k3.dy + k4.dy);
    p.yaw_rad += h / 6 * (k1.dyaw + 2 * k2.dyaw + 2 * k3.dyaw + k4.dyaw);
  }
  bases_.push_back(Pose{});
}

BodyMotion Trajectory::motion(double t_s) const {
  if (loop_) {
    const double n = std::floor(t_s / period_s_);
    t_s -= n * period_s_;
  }
  return scenario_.motion(std::max(t_s, 0.0));
}

BodyPose Trajectory::body(double t_s) const {
  if (!scenario_.body) return {};
  if (loop_) {
    const double n = std::floor(t_s / period_s_);
    t_s -= n * period_s_;
  }
  return scenario_.body(std::max(t_s, 0.0));
}

Pose Trajectory::pose_in_period(double tau) const {
  tau = std::max(tau, 0.0);
  const double last = static_cast<double>(table_.size() - 2) * step_s_;
  if (tau > last) {
    // Beyond the table (a non-looping run read past its end): integrate on.
    Pose p = table_[table_.size() - 2];
    double t = last;
    while (t < tau) {
      const double h = std::min(step_s_, tau - t);
      const PoseRate k = rate(scenario_.motion(t + h / 2), p.yaw_rad + h / 2 * rate(scenario_.motion(t), p.yaw_rad).dyaw);
      p.x_m += h * k.dx;
      p.y_m += h * k.dy;
      p.yaw_rad += h * k.dyaw;
      t += h;
    }
    return p;
  }
  const double u = tau / step_s_;
  const auto i = static_cast<std::size_t>(std::floor(u));
  const double a = u - static_cast<double>(i);
  const Pose& p0 = table_[i];
  const Pose& p1 = table_[i + 1];
  const double t0 = static_cast<double>(i) * step_s_;
  const PoseRate r0 = rate(scenario_.motion(t0), p0.yaw_rad);
  const PoseRate r1 = rate(scenario_.motion(t0 + step_s_), p1.yaw_rad);
  // Cubic Hermite basis.
  const double h00 = (1 + 2 * a) * (1 - a) * (1 - a);
  const double h10 = a * (1 - a) * (1 - a);
  const double h01 = a * a * (3 - 2 * a);
  const double h11 = a * a * (a - 1);
  const double h = step_s_;
  return {h00 * p0.x_m + h10 * h * r0.dx + h01 * p1.x_m + h11 * h * r1.dx,
          h00 * p0.y_m + h10 * h * r0.dy + h01 * p1.y_m + h11 * h * r1.dy,
          h00 * p0.yaw_rad + h10 * h * r0.dyaw + h01 * p1.yaw_rad + h11 * h * r1.dyaw};
}

Pose Trajectory::loop_base(std::int64_t n) const {
  if (n <= 0) return Pose{};
  const Pose end = pose_in_period(period_s_);
  while (static_cast<std::int64_t>(bases_.size()) <= n) bases_.push_back(compose(bases_.back(), end));
  return bases_[static_cast<std::size_t>(n)];
}

Pose Trajectory::pose(double t_s) const {
  if (!loop_) return pose_in_period(t_s);
  const double nf = std::floor(t_s / period_s_);
  const Pose rel = pose_in_period(t_s - nf * period_s_);
  return compose(loop_base(static_cast<std::int64_t>(nf)), rel);
}

}  // namespace gvs::drivers::sim
