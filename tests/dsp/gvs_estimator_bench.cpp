// Time per frame of the gvs estimator alone, per frame kind, and of the
// thesis's methods on the same frames (docs/performance.md).
//   build/<dir>/tests/dsp/gvs_estimator_bench
//
// Each kind is one second (60 frames, 512x384) of the simulator at a constant
// velocity, rendered once with the exposure the gvs closed loop chose (so the
// frames are what the estimator meets on the car), then fed to a fresh
// estimator round and round with the clock running on. The label names the
// method the estimator used on the last frame, so the path measured is shown.
// BM_LaserDots: finding and masking the laser dots on the same kinds of
// frame rendered with the design's dots.
#include <benchmark/benchmark.h>

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "gvs/drivers/simulator.hpp"
#include "gvs/dsp/estimator.hpp"
#include "gvs/dsp/exposure_control.hpp"
#include "gvs/dsp/gvs_estimator.hpp"
#include "gvs/dsp/laser_dots.hpp"

namespace {

using namespace gvs;

struct FrameKind {
  const char* name;
  double vx_mps;
  double vy_mps;
  dsp::ExposureMode mode;  ///< fixed: 3 ms continuous light
};

// sharp pair: 1.8 km/h, consecutive frames overlap (pair correlation);
// blurred: 54 km/h with 3 ms, the streak is longer than the frame (direction only);
// strobed: 108 km/h, one strobe keeping the streak 10-80 px;
// double pulse: 108 km/h, two short pulses.
constexpr FrameKind kKinds[] = {
    {"sharp_pair", 0.5, 0.02, dsp::ExposureMode::fixed},
    {"blurred", 15.0, 0.8, dsp::ExposureMode::fixed},
    {"strobed", 30.0, 1.5, dsp::ExposureMode::adaptive},
    {"double_pulse", 30.0, 1.5, dsp::ExposureMode::double_pulse},
};

constexpr int kFrames = 60;

std::vector<dsp::FrameView> render(const FrameKind& kind, bool lasers = false) {
  drivers::SimulatorConfig cfg;
  cfg.seconds = 1.5;
  if (lasers) cfg.lasers = core::design_laser_geometry(cfg.camera, cfg.camera_height_mm);
  drivers::Simulator sim(cfg, drivers::sim::constant_motion_scenario(kind.vx_mps, kind.vy_mps, 0.0, 1.5));
  dsp::EstimatorConfig ec;
  ec.method = "gvs";
  ec.camera = cfg.camera;
  dsp::GvsEstimator est(ec);
  const dsp::ExposureLimits limits = dsp::exposure_limits_for(cfg.camera, cfg.fps);
  dsp::ExposurePlan plan;
  std::vector<dsp::FrameView> frames;
  drivers::SimFrame f;
  // The first 0.5 s let the exposure loop settle; the last second is kept.
  const std::size_t settle = sim.frame_count() - kFrames;
  for (std::size_t i = 0; sim.next(f); ++i) {
    const dsp::FrameView view{f.gray, f.record.index, f.record.t_ns, f.record.exposure};
    const dsp::VelocityEstimate e = est.estimate(view);
    if (i >= settle) frames.push_back({f.gray.clone(), f.record.index, f.record.t_ns, f.record.exposure});
    if (kind.mode != dsp::ExposureMode::fixed) {
      plan = dsp::next_exposure(e, plan, kind.mode, limits);
      sim.set_exposure(plan);
    }
  }
  return frames;
}

const std::vector<dsp::FrameView>& frames_of(const FrameKind& kind) {
  static std::map<std::string, std::vector<dsp::FrameView>> cache;
  auto it = cache.find(kind.name);
  if (it == cache.end()) it = cache.emplace(kind.name, render(kind)).first;
  return it->second;
}

const std::vector<dsp::FrameView>& laser_frames_of(const FrameKind& kind) {
  static std::map<std::string, std::vector<dsp::FrameView>> cache;
  auto it = cache.find(kind.name);
  if (it == cache.end()) it = cache.emplace(kind.name, render(kind, /*lasers=*/true)).first;
  return it->second;
}

/// What the laser dots add per frame in dsp::FrameProcessor: finding them
/// and masking them in a copy of the frame (the same kinds of frame, the
/// design's three dots lit; docs/performance.md). The label is the share of
/// frames with a height.
void BM_LaserDots(benchmark::State& state, const FrameKind& kind) {
  const std::vector<dsp::FrameView>& frames = laser_frames_of(kind);
  const core::CameraGeometry camera;
  dsp::LaserDotFinder finder(camera, 60.0, core::design_laser_geometry(camera, 60.0));
  cv::Mat masked = frames.front().gray.clone();
  std::int64_t n = 0, with_height = 0;
  for (auto _ : state) {
    const cv::Mat& gray = frames[static_cast<std::size_t>(n) % frames.size()].gray;
    const dsp::LaserDotResult r = finder.find(gray);
    gray.copyTo(masked);
    finder.mask(r, masked);
    benchmark::DoNotOptimize(masked.data);
    with_height += r.ride.has_height ? 1 : 0;
    ++n;
  }
  state.counters["height_frac"] = n ? static_cast<double>(with_height) / static_cast<double>(n) : 0.0;
}

void BM_Estimator(benchmark::State& state, const FrameKind& kind, const char* method) {
  const std::vector<dsp::FrameView>& frames = frames_of(kind);
  dsp::EstimatorConfig cfg;
  cfg.method = method;
  const auto est = dsp::make_estimator(cfg);
  const std::int64_t period_ns = frames.back().t_ns - frames.front().t_ns + 16'666'667;
  std::int64_t n = 0;
  const char* last_method = "";
  std::int64_t with_speed = 0;
  for (auto _ : state) {
    const std::size_t i = static_cast<std::size_t>(n) % frames.size();
    dsp::FrameView f = frames[i];
    const std::int64_t lap = n / static_cast<std::int64_t>(frames.size());
    f.t_ns += lap * period_ns;
    f.index += lap * static_cast<std::int64_t>(frames.size());
    const dsp::VelocityEstimate e = est->estimate(f);
    benchmark::DoNotOptimize(e);
    last_method = dsp::method_word(e.method);
    with_speed += e.has_speed ? 1 : 0;
    ++n;
  }
  state.SetLabel(last_method);
  state.counters["speed_frac"] = n ? static_cast<double>(with_speed) / static_cast<double>(n) : 0.0;
}

void register_all() {
  for (const FrameKind& kind : kKinds) {
    const std::string dots = std::string("BM_LaserDots/") + kind.name;
    benchmark::RegisterBenchmark(dots.c_str(), BM_LaserDots, kind)->Unit(benchmark::kMillisecond);
    for (const char* method : {"gvs", "thesis", "thesis-orb", "thesis-fft", "thesis-laplacian"}) {
      const std::string name = std::string("BM_Estimator/") + kind.name + "/" + method;
      benchmark::RegisterBenchmark(name.c_str(), BM_Estimator, kind, method)->Unit(benchmark::kMillisecond);
    }
  }
}

}  // namespace

int main(int argc, char** argv) {
  register_all();
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
