// Runs the gvs estimator on simulator frames (optionally with closed-loop
// exposure control) and scores it against the truth, per speed band of the
// accuracy targets (docs/accuracy.md). Used by gvs_accuracy_test.cpp and gvs_sim_eval.cpp.
#pragma once

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <map>
#include <string>

#include "gvs/can/codec.hpp"
#include "gvs/drivers/simulator.hpp"
#include "gvs/dsp/exposure_control.hpp"
#include "gvs/dsp/vocabulary.hpp"
#include "gvs/dsp/gvs_estimator.hpp"

namespace gvs::test {

/// Speed bands (km/h) of the accuracy table; band -1 below 0.5 km/h.
inline constexpr std::array<double, 6> kBandEdgesKmh{0.5, 5.0, 15.0, 60.0, 140.0, 250.0};

inline int band_of(double speed_mps) {
  const double kmh = speed_mps * 3.6;
  for (std::size_t i = 0; i + 1 < kBandEdgesKmh.size(); ++i) {
    if (kmh >= kBandEdgesKmh[i] && kmh < kBandEdgesKmh[i + 1]) return static_cast<int>(i);
  }
  return -1;
}

struct BandScore {
  int frames = 0;
  int with_direction = 0;
  int with_speed = 0;
  int valid_speed = 0;  ///< ... at a quality the bus sends as valid (can::ValidityRule's default)
  double dir_sq = 0.0;
  double dir_max = 0.0;
  double speed_sq = 0.0;  ///< relative error squared
  double speed_max = 0.0; ///< relative
  [[nodiscard]] double dir_rms() const { return with_direction ? std::sqrt(dir_sq / with_direction) : 0.0; }
  [[nodiscard]] double speed_rms() const { return with_speed ? std::sqrt(speed_sq / with_speed) : 0.0; }
  [[nodiscard]] double dir_coverage() const { return frames ? double(with_direction) / frames : 0.0; }
  [[nodiscard]] double speed_coverage() const { return frames ? double(with_speed) / frames : 0.0; }
  [[nodiscard]] double valid_speed_coverage() const { return frames ? double(valid_speed) / frames : 0.0; }
};

struct RunScore {
  std::array<BandScore, 5> bands{};
  int still_frames = 0;        ///< truth speed < 0.01 m/s
  int still_ok = 0;            ///< ... reported with speed < 0.01 m/s and no direction
  double still_speed_max = 0.0;
  int yaw_frames = 0;
  double yaw_sq = 0.0;
  double yaw_max_dps = 0.0;  ///< largest yaw rate error of a frame that gives one
  std::map<std::string, int> methods;
  int frames = 0;
  /// Frames whose direction is off by > 1 deg or speed by > 5 %, yet quality >= 0.5.
  int confident_bad = 0;
  /// Frames whose speed is off by > 5 % (truth >= 1 km/h) at a quality the
  /// bus sends as valid (can::ValidityRule's default min_quality): must be 0.
  int valid_speed_off = 0;
  /// Frames whose direction points more than 90 deg from the truth (truth
  /// >= 1 km/h) at a quality the bus sends as valid: must be 0.
  int valid_direction_reversed = 0;
  double estimate_ms_total = 0.0;  ///< wall time inside estimate()
  [[nodiscard]] double yaw_rms() const { return yaw_frames ? std::sqrt(yaw_sq / yaw_frames) : 0.0; }
};

/// Simulates `config` and scores the estimator. `mode` closes the exposure
/// loop through next_exposure(); `skip_s` ignores the first seconds (start-up).
inline RunScore run_and_score(drivers::Simulator& sim, dsp::ExposureMode mode, double skip_s = 0.0,
                              bool verbose = false, const dsp::GvsEstimatorSettings& settings = {}) {
  const drivers::SimulatorConfig& config = sim.config();
  dsp::EstimatorConfig ec;
  ec.method = "gvs";
  ec.camera = config.camera;
  dsp::GvsEstimator est(ec, settings);
  const dsp::ExposureLimits limits = dsp::exposure_limits_for(config.camera, config.fps);
  dsp::ExposurePlan plan;
  plan.exposure_us = config.exposure_us;
  RunScore score;
  drivers::SimFrame f;
  std::int64_t t0 = -1;
  while (sim.next(f)) {
    dsp::FrameView view{f.gray, f.record.index, f.record.t_ns, f.record.exposure};
    const auto t_start = std::chrono::steady_clock::now();
    const dsp::VelocityEstimate e = est.estimate(view);
    score.estimate_ms_total +=
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t_start).count();
    if (mode != dsp::ExposureMode::fixed) {
      const dsp::ExposurePlan next = dsp::next_exposure(e, plan, mode, limits);
      plan = next;
      sim.set_exposure(plan);
    }
    if (t0 < 0) t0 = f.record.t_ns;
    if (static_cast<double>(f.record.t_ns - t0) * 1e-9 < skip_s) continue;
    ++score.frames;
    ++score.methods[dsp::method_word(e.method)];
    const drivers::TruthRecord& t = f.truth;
    if (verbose) {
      std::printf("%5lld truth %7.3f m/s %8.3f deg yaw %7.2f | est %s%7.3f %s%8.3f yaw %s%7.2f q %.2f %s exp %.1f/%zu snr %.1f\n",
                  static_cast<long long>(f.record.index), t.speed_mps, t.direction_deg.value_or(0.0),
                  t.yaw_rate_dps, e.has_speed ? " " : "-", e.speed_mps, e.has_direction ? " " : "-",
                  e.direction_deg, e.has_yaw_rate ? " " : "-", e.yaw_rate_dps, e.quality, dsp::method_word(e.method),
                  f.record.exposure.exposure_us, f.record.exposure.pulse_count, e.texture_snr);
    }
    if (e.has_yaw_rate) {
      ++score.yaw_frames;
      const double yaw_error_dps = e.yaw_rate_dps - t.yaw_rate_dps;
      score.yaw_sq += yaw_error_dps * yaw_error_dps;
      score.yaw_max_dps = std::max(score.yaw_max_dps, std::abs(yaw_error_dps));
    }
    if (t.speed_mps < dsp::VelocityEstimate::kStandstillMps) {
      ++score.still_frames;
      if (e.has_speed && e.speed_mps < 0.01 && !e.has_direction) ++score.still_ok;
      if (e.has_speed) score.still_speed_max = std::max(score.still_speed_max, e.speed_mps);
      continue;
    }
    const int b = band_of(t.speed_mps);
    if (b < 0) continue;
    BandScore& s = score.bands[static_cast<std::size_t>(b)];
    ++s.frames;
    bool bad = false;
    const bool valid = can::quality_passes(e.quality, can::ValidityRule{}.min_quality);  // as the bus sends it
    if (e.has_direction && t.direction_deg) {
      const double err = std::abs(dsp::wrap_deg(e.direction_deg - *t.direction_deg));
      bad = bad || err > 1.0;
      ++s.with_direction;
      s.dir_sq += err * err;
      s.dir_max = std::max(s.dir_max, err);
      if (err > 90.0 && t.speed_mps >= 1.0 / 3.6 && valid) {
        ++score.valid_direction_reversed;
      }
    }
    if (e.has_speed) {
      const double rel = std::abs(e.speed_mps / t.speed_mps - 1.0);
      ++s.with_speed;
      if (valid) ++s.valid_speed;
      s.speed_sq += rel * rel;
      s.speed_max = std::max(s.speed_max, rel);
      bad = bad || rel > 0.05;
      if (rel > 0.05 && t.speed_mps >= 1.0 / 3.6 && valid) {
        ++score.valid_speed_off;
      }
    }
    if (bad && e.quality >= 0.5) ++score.confident_bad;
  }
  return score;
}

/// The same for a built-in scenario (config.scenario).
inline RunScore run_and_score(const drivers::SimulatorConfig& config, dsp::ExposureMode mode,
                              double skip_s = 0.0, bool verbose = false) {
  drivers::Simulator sim(config);
  return run_and_score(sim, mode, skip_s, verbose);
}

inline void print_score(const char* title, const RunScore& s) {
  std::printf("%s: %d frames\n", title, s.frames);
  std::printf("  band km/h   frames  dir%%   dir rms/max deg   speed%%  speed rms/max %%\n");
  for (std::size_t i = 0; i < s.bands.size(); ++i) {
    const BandScore& b = s.bands[i];
    if (b.frames == 0) continue;
    std::printf("  %5.1f-%-5.0f %6d  %5.1f   %6.3f / %6.3f   %5.1f   %6.3f / %6.3f\n", kBandEdgesKmh[i],
                kBandEdgesKmh[i + 1], b.frames, 100.0 * b.dir_coverage(), b.dir_rms(), b.dir_max,
                100.0 * b.speed_coverage(), 100.0 * b.speed_rms(), 100.0 * b.speed_max);
  }
  if (s.still_frames > 0) {
    std::printf("  standstill %d frames, %d correct, max reported speed %.4f m/s\n", s.still_frames,
                s.still_ok, s.still_speed_max);
  }
  if (s.yaw_frames > 0) {
    std::printf("  yaw rate on %d frames, rms error %.2f deg/s, max %.1f deg/s\n", s.yaw_frames, s.yaw_rms(),
                s.yaw_max_dps);
  }
  std::printf("  frames off by > 1 deg or > 5 %% with quality >= 0.5: %d\n", s.confident_bad);
  std::printf("  speeds off by > 5 %% valid on the bus: %d\n", s.valid_speed_off);
  if (s.frames > 0) std::printf("  estimate(): %.2f ms per frame (mean)\n", s.estimate_ms_total / s.frames);
  std::printf("  methods:");
  for (const auto& [m, n] : s.methods) std::printf(" %s=%d", m.c_str(), n);
  std::printf("\n");
}

}  // namespace gvs::test
