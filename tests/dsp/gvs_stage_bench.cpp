// Time of each stage of the gvs estimator on its own (docs/performance.md,
// "Against FFTW's real-to-complex transform, per stage"): the stages of
// eval::estimator_stages() (the table `gvs replay --timing` times too), each
// on the first frames of the kind whose path runs it, and two yardsticks:
// FFTW's r2c planned with FFTW_MEASURE and cv::dft. Registered by
// gvs_estimator_bench.cpp's main; run alone with --benchmark_filter=BM_Stage.
#include <benchmark/benchmark.h>

#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <opencv2/core.hpp>

#include "gvs/eval/estimator_stages.hpp"
#include "gvs_bench_frames.hpp"

namespace gvs::bench {

namespace {

// Spectra are 1.5 MB each: a few frames are enough for the stages.
constexpr std::size_t kStagePairs = 4;

/// The kind's first frames; `lasers`: rendered with the design's four dots lit.
const eval::StageInputs& inputs_of(const char* kind_name, bool lasers = false) {
  static std::vector<std::pair<std::string, eval::StageInputs>> cache;
  const std::string key = std::string(kind_name) + (lasers ? "+lasers" : "");
  for (const auto& [name, in] : cache) {
    if (name == key) return in;
  }
  const FrameKind& kind = kind_named(kind_name);
  const std::vector<dsp::FrameView>& frames = lasers ? laser_frames_of(kind) : frames_of(kind);
  std::vector<std::pair<cv::Mat, cv::Mat>> pairs;
  for (std::size_t i = 0; i < kStagePairs && 2 * i + 1 < frames.size(); ++i) {
    pairs.emplace_back(frames[2 * i].gray, frames[2 * i + 1].gray);
  }
  std::optional<eval::LaserStageSetup> head;
  if (lasers) {
    const core::CameraGeometry camera;
    head = eval::LaserStageSetup{camera, kLaserHeightMm, core::design_laser_geometry(camera, kLaserHeightMm)};
  }
  cache.emplace_back(key, eval::make_stage_inputs(pairs, head));
  return cache.back().second;
}

void add(const std::string& stage, const char* kind, void (*body)(benchmark::State&, const eval::StageInputs&)) {
  const std::string name = "BM_Stage/" + stage + "/" + kind;
  benchmark::RegisterBenchmark(name.c_str(), [body, kind](benchmark::State& state) {
    body(state, inputs_of(kind));
  })->Unit(benchmark::kMillisecond);
}

}  // namespace

void register_stage_benchmarks() {
  // --- yardsticks, 512x384 ---
  add("fftw_r2c_measure", "blurred", [](benchmark::State& state, const eval::StageInputs& in) {
    FftwR2c r2c(in.size);
    r2c.load(in.gray.front());
    for (auto _ : state) r2c.run();
  });
  add("cv_dft_forward", "blurred", [](benchmark::State& state, const eval::StageInputs& in) {
    cv::Mat out(in.size, CV_32FC2);
    std::size_t i = 0;
    for (auto _ : state) cv::dft(in.windowed[i++ % in.windowed.size()], out, cv::DFT_COMPLEX_OUTPUT);
  });
  // --- the estimator's stages ---
  for (const eval::EstimatorStage& stage : eval::estimator_stages()) {
    const std::string name = std::string("BM_Stage/") + stage.name + "/" + stage.kind;
    benchmark::RegisterBenchmark(name.c_str(), [&stage](benchmark::State& state) {
      const eval::StageInputs& in = inputs_of(stage.kind, stage.needs_lasers);
      const std::size_t n = stage.steps(in);
      const auto step = stage.prepare(in);
      std::size_t i = 0;
      for (auto _ : state) step(i++ % n);
    })->Unit(benchmark::kMillisecond);
  }
}

}  // namespace gvs::bench
