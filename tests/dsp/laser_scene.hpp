// The laser-dot tests' scenes (laser_dots_test.cpp, laser_wrong_dots_test.cpp):
// the design's four-beam head over simulated ground, level or standing, and
// what a test paints on a frame (white grains, a dot dimmed or blotted out).
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

#include <opencv2/core/mat.hpp>

#include "gvs/core/laser_geometry.hpp"
#include "gvs/drivers/simulator.hpp"
#include "gvs/dsp/laser_dots.hpp"

namespace gvs::dsp::laser_test {

inline constexpr double kNominalMm = 60.0;
/// How far a dot's light reaches, px: its spot is 8x the ring's light and
/// saturates, so its tails stay bright well beyond the spot's sigma; a dot
/// blotted or dimmed over less leaves a bright ring a few pixels out.
inline constexpr double kDotReachPx = 8.0;

inline drivers::SimulatorConfig laser_config(std::uint64_t seed = 5) {
  drivers::SimulatorConfig c;
  c.seed = seed;
  c.lasers = core::design_laser_geometry(c.camera, kNominalMm);
  return c;
}

inline drivers::sim::Scenario standing(drivers::sim::BodyPose pose, double vx_mps = 0.0, double vy_mps = 0.0) {
  drivers::sim::Scenario s = drivers::sim::constant_motion_scenario(vx_mps, vy_mps);
  s.body = [pose](double) { return pose; };
  return s;
}

inline core::ExposurePlan double_pulse() {
  core::ExposurePlan p;
  p.exposure_us = 340.0;
  p.pulse_count = 2;
  p.pulses[0] = {0.0, 6.667};
  p.pulses[1] = {333.333, 6.667};
  return p;
}

/// Frame 4 of a double pulse at 8 m/s, the body level at the nominal height.
inline drivers::SimFrame level_frame(const drivers::SimulatorConfig& c) {
  drivers::Simulator sim(c, standing({0.0, 0.0, 0.0}, 8.0, 0.0));
  drivers::SimFrame f;
  sim.render(4, double_pulse(), f);
  return f;
}

/// The design's head over level ground (level_frame), a finder for its
/// four beams, and what that finds on the frame as rendered.
struct LevelScene {
  drivers::SimulatorConfig c = laser_config();
  drivers::SimFrame f = level_frame(c);
  LaserDotFinder finder{c.camera, kNominalMm, c.lasers};
  LaserDotResult clean = finder.find(f.gray);
};

/// The point `shift_px` from dot `k` along its track, towards a higher ground.
inline void along_track(const drivers::SimulatorConfig& c, const LaserDot& dot, std::size_t k, double shift_px, double& row,
                 double& col) {
  double r_hi = 0.0, c_hi = 0.0;
  const core::LaserBeam& b = c.lasers.beams[k];
  core::head_to_pixel(c.camera, kNominalMm, b.origin_mm() + ((kNominalMm + 5.0 + b.z_mm) / -b.direction().z) * b.direction(),
                      r_hi, c_hi);
  const double len = std::hypot(r_hi - dot.row, c_hi - dot.col);
  row = dot.row + shift_px * (r_hi - dot.row) / len;
  col = dot.col + shift_px * (c_hi - dot.col) / len;
}

/// `gray` with white grains (255, 2 px, a ring of `background` around) at
/// `grains` and the dots of `dimmed` (within kDotReachPx) dimmed to `gain`
/// of their contrast over `background`.
inline cv::Mat with_grains(const cv::Mat& gray, const std::vector<std::array<double, 2>>& grains,
                    const std::vector<const LaserDot*>& dimmed, double gain, double background) {
  cv::Mat out = gray.clone();
  for (int r = 0; r < out.rows; ++r) {
    for (int cc = 0; cc < out.cols; ++cc) {
      double v = out.at<std::uint8_t>(r, cc);
      for (const LaserDot* d : dimmed)
        if (std::hypot(r - d->row, cc - d->col) <= kDotReachPx) v = background + (v - background) * gain;
      for (const auto& [gr, gc] : grains) {
        const double d_grain = std::hypot(r - gr, cc - gc);
        if (d_grain <= 2.0) v = 255.0;
        else if (d_grain <= 5.0) v = background;
      }
      out.at<std::uint8_t>(r, cc) = static_cast<std::uint8_t>(std::clamp(std::lround(v), 0L, 255L));
    }
  }
  return out;
}

/// `gray` with dot `dot` blotted out: the ground beside it over kDotReachPx.
inline cv::Mat blotted(const cv::Mat& gray, const LaserDot& dot) {
  return with_grains(gray, {}, {&dot}, 0.0, dot.mask_background_dn);
}

/// A standing car over white grains on tracks 1 and 3, 40 px along them
/// from the dots, in both frames (the ground does not move); the body
/// rises by `rise_mm` between them (frames 4 and 5 of `plan`).
struct StandingPair {
  drivers::SimulatorConfig c = laser_config();
  core::ExposurePlan plan;
  drivers::SimFrame f0, f1;
  LaserDotResult clean0, clean1;  ///< the frames as rendered, each alone
  std::vector<std::array<double, 2>> grains;
  StandingPair(const core::ExposurePlan& light, double rise_mm) : plan(light) {
    drivers::Simulator(c, standing({0.0, 0.0, 0.0})).render(4, plan, f0);
    drivers::Simulator(c, standing({rise_mm, 0.0, 0.0})).render(5, plan, f1);
    LaserDotFinder alone(c.camera, kNominalMm, c.lasers);
    clean0 = alone.find(f0.gray);
    clean1 = alone.find(f1.gray);
    for (const std::size_t k : {std::size_t{1}, std::size_t{3}}) {
      std::array<double, 2> g{};
      along_track(c, clean0.dots[k], k, 40.0, g[0], g[1]);
      grains.push_back(g);
    }
  }
  [[nodiscard]] std::int64_t t_mid(const drivers::SimFrame& f) const {
    return core::mid_exposure_ns(f.record.t_ns, plan);
  }
};

/// StandingPair on sharp ground (3 ms of continuous light) rising by 1 mm
/// (the image scales by 1.7 %), dots 0 and 2 of the second frame dimmed to
/// a fifth of their contrast (dark stones): no plane of the second frame's
/// own spots holds, nor of the plain difference of the two; against the
/// first scaled by the heave the four dots stand out.
struct HeavedStandingPair : StandingPair {
  cv::Mat frame0, frame1;  ///< with the grains and the dimmed dots
  HeavedStandingPair() : StandingPair(continuous_3ms(), 1.0) {
    frame0 = with_grains(f0.gray, grains, {}, 1.0, clean0.dots[0].mask_background_dn);
    frame1 = with_grains(f1.gray, grains, {&clean1.dots[0], &clean1.dots[2]}, 0.2, clean1.dots[0].mask_background_dn);
  }
  static core::ExposurePlan continuous_3ms() {
    core::ExposurePlan p;
    p.exposure_us = 3000.0;
    return p;
  }
};

}  // namespace gvs::dsp::laser_test
