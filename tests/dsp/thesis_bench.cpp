// Time per frame of the thesis baseline's methods on a 512x384 frame.
//   build/<dir>/tests/dsp/thesis_bench
#include <benchmark/benchmark.h>

#include "gvs/dsp/thesis.hpp"
#include "gvs/dsp/thesis_orb_methods.hpp"
#include "thesis_synth.hpp"

namespace {

using namespace gvs::dsp;

constexpr int kW = 512;
constexpr int kH = 384;

struct Frames {
  cv::Mat a;
  cv::Mat b;
  Frames() {
    const cv::Mat t = test::blob_texture(kW + 100, kH + 100, 21);
    a = test::line_blurred_crop(t, 3.0, 6.0, kW, kH);
    const cv::Mat moved = test::shifted_crop(t, 20.0, 2.0, kW + 100, kH + 100);
    b = test::line_blurred_crop(moved, 3.0, 6.0, kW, kH);
  }
};
const Frames& frames() {
  static const Frames f;
  return f;
}

void BM_OrbFrameDifference(benchmark::State& state) {
  thesis::OrbFrameDifference orb;
  orb.set_previous(frames().a);
  bool flip = false;
  for (auto _ : state) {
    benchmark::DoNotOptimize(orb.measure_and_advance(flip ? frames().a : frames().b));
    flip = !flip;
  }
}
BENCHMARK(BM_OrbFrameDifference)->Unit(benchmark::kMillisecond);

void BM_FftOrientation(benchmark::State& state) {
  thesis::FftOrientation fft(kW, kH);
  for (auto _ : state) benchmark::DoNotOptimize(fft.measure(frames().a));
}
BENCHMARK(BM_FftOrientation)->Unit(benchmark::kMillisecond);

void BM_LaplacianStd(benchmark::State& state) {
  thesis::LaplacianBlur lap(0.1);
  for (auto _ : state) benchmark::DoNotOptimize(lap.lap_std(frames().a));
}
BENCHMARK(BM_LaplacianStd)->Unit(benchmark::kMillisecond);

void BM_Estimator(benchmark::State& state, const char* method) {
  EstimatorConfig cfg;
  cfg.method = method;
  const auto est = make_estimator(cfg);
  FrameView f;
  std::int64_t i = 0;
  for (auto _ : state) {
    f.gray = (i % 2 == 0) ? frames().a : frames().b;
    f.index = i;
    f.t_ns = i * 16'666'667;
    benchmark::DoNotOptimize(est->estimate(f));
    ++i;
  }
}
BENCHMARK_CAPTURE(BM_Estimator, thesis_orb, "thesis-orb")->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Estimator, thesis_fft, "thesis-fft")->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Estimator, thesis_laplacian, "thesis-laplacian")->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Estimator, thesis, "thesis")->Unit(benchmark::kMillisecond);

}  // namespace
