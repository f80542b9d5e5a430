// Time per frame of the gvs estimator alone, per frame kind, and of the
// thesis's methods on the same frames, each beside FFTW's real-to-complex
// transform of the same frames (docs/performance.md).
//   build/<dir>/tests/dsp/gvs_estimator_bench
//
// Each kind is one second (60 frames, 512x384) of the simulator at a constant
// velocity (on the procedural asphalt, or on a photograph of real asphalt:
// blurred_photo), rendered once with the exposure the gvs closed loop chose (so the
// frames are what the estimator meets on the car), then fed to a fresh
// estimator round and round with the clock running on. The label names the
// method the estimator used on the last frame, so the path measured is shown.
// Counters: r2c_ms, FFTW's r2c of the same frames timed right after the
// estimator (thread CPU time, like the estimator's), and x_r2c, the
// estimator's time over it (issue #22's target: at most 3). The per-stage
// costs are in gvs_stage_bench.cpp (the same program).
// BM_LaserDots: finding and masking the laser dots on the same kinds of
// frame rendered with the design's dots; BM_LaserDotsScaledLook: step 5 of a
// sequence on a standing car (laser_scene.hpp).
#include <benchmark/benchmark.h>

#include <cstdint>
#include <exception>
#include <string>
#include <vector>

#include "gvs/dsp/estimator.hpp"
#include "gvs/dsp/laser_dots.hpp"
#include "gvs_bench_frames.hpp"
#include "laser_scene.hpp"

namespace {

using namespace gvs;
using bench::FrameKind;

/// The kind's frames, or none after SkipWithError (a photograph not found).
template <typename Frames>
const std::vector<dsp::FrameView>* frames_or_skip(benchmark::State& state, Frames of, const FrameKind& kind) {
  try {
    return &of(kind);
  } catch (const std::exception& e) {
    state.SkipWithError(e.what());
    return nullptr;
  }
}

/// What the laser dots add per frame in dsp::FrameProcessor: copying the
/// frame, finding them in the copy and masking them there, in that order
/// (the same kinds of frame, the design's four dots lit; docs/performance.md).
/// The counter is the share of frames with a height.
void BM_LaserDots(benchmark::State& state, const FrameKind& kind) {
  const std::vector<dsp::FrameView>* rendered = frames_or_skip(state, bench::laser_frames_of, kind);
  if (rendered == nullptr) return;
  const std::vector<dsp::FrameView>& frames = *rendered;
  const core::CameraGeometry camera;
  dsp::LaserDotFinder finder(camera, bench::kLaserHeightMm, core::design_laser_geometry(camera, bench::kLaserHeightMm));
  cv::Mat masked = frames.front().gray.clone();
  std::int64_t n = 0, with_height = 0;
  for (auto _ : state) {
    const cv::Mat& gray = frames[static_cast<std::size_t>(n) % frames.size()].gray;
    const dsp::LaserDotResult r = finder.find_and_mask(gray, masked);
    benchmark::DoNotOptimize(masked.data);
    with_height += r.ride.has_height ? 1 : 0;
    ++n;
  }
  state.counters["height_frac"] = n ? static_cast<double>(with_height) / static_cast<double>(n) : 0.0;
}

/// Step 5 of a sequence: a standing car's two frames of
/// laser_scene.hpp's HeavedStandingPair, the second's plane found only
/// against the first scaled by the heave; per iteration both frames (copy +
/// find + mask, as FrameProcessor runs them), the finder forgetting the
/// sequence in between. The counter is the share of second frames with a height.
void BM_LaserDotsScaledLook(benchmark::State& state) {
  const dsp::laser_test::HeavedStandingPair pair;
  dsp::LaserDotFinder finder(pair.c.camera, dsp::laser_test::kNominalMm, pair.c.lasers);
  cv::Mat masked = pair.frame0.clone();
  std::int64_t n = 0, with_height = 0;
  for (auto _ : state) {
    finder.forget();
    (void)finder.find_and_mask(pair.frame0, masked, pair.t_mid(pair.f0), pair.plan.exposure_us);
    const dsp::LaserDotResult r = finder.find_and_mask(pair.frame1, masked, pair.t_mid(pair.f1), pair.plan.exposure_us);
    benchmark::DoNotOptimize(masked.data);
    with_height += r.ride.has_height ? 1 : 0;
    ++n;
  }
  state.counters["height_frac"] = n ? static_cast<double>(with_height) / static_cast<double>(n) : 0.0;
}

void BM_Estimator(benchmark::State& state, const FrameKind& kind, const char* method) {
  const std::vector<dsp::FrameView>* rendered = frames_or_skip(state, bench::frames_of, kind);
  if (rendered == nullptr) return;
  const std::vector<dsp::FrameView>& frames = *rendered;
  dsp::EstimatorConfig cfg;
  cfg.method = method;
  const auto est = dsp::make_estimator(cfg);
  const std::int64_t period_ns = frames.back().t_ns - frames.front().t_ns + 16'666'667;
  std::int64_t n = 0;
  const char* last_method = "";
  std::int64_t with_speed = 0;
  const double cpu0 = bench::thread_cpu_s();
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
  const double estimator_ms = n ? 1e3 * (bench::thread_cpu_s() - cpu0) / static_cast<double>(n) : 0.0;
  // The reference in the same run, on the same frames, right after.
  static bench::FftwR2c r2c(frames.front().gray.size());
  const double r2c_ms = r2c.ms_per_frame(frames, 3);
  state.SetLabel(last_method);
  state.counters["speed_frac"] = n ? static_cast<double>(with_speed) / static_cast<double>(n) : 0.0;
  state.counters["r2c_ms"] = r2c_ms;
  state.counters["x_r2c"] = r2c_ms > 0.0 ? estimator_ms / r2c_ms : 0.0;
}

void register_all() {
  benchmark::RegisterBenchmark("BM_LaserDotsScaledLook", BM_LaserDotsScaledLook)->Unit(benchmark::kMillisecond);
  for (const FrameKind& kind : bench::kKinds) {
    const std::string dots = std::string("BM_LaserDots/") + kind.name;
    benchmark::RegisterBenchmark(dots.c_str(), BM_LaserDots, kind)->Unit(benchmark::kMillisecond);
    for (const char* method : {"gvs", "thesis", "thesis-orb", "thesis-fft", "thesis-laplacian"}) {
      const std::string name = std::string("BM_Estimator/") + kind.name + "/" + method;
      benchmark::RegisterBenchmark(name.c_str(), BM_Estimator, kind, method)->Unit(benchmark::kMillisecond);
    }
  }
}

}  // namespace

namespace gvs::bench {
void register_stage_benchmarks();  // gvs_stage_bench.cpp
}

int main(int argc, char** argv) {
  register_all();
  gvs::bench::register_stage_benchmarks();
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
