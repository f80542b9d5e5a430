// Time of each stage of the gvs estimator on its own (docs/performance.md,
// "Estimator per stage"): the transforms, and the passes over the spectrum
// or the frame that the frame kinds run (a stage's kind: the one whose
// path runs it). Registered by gvs_estimator_bench.cpp's main; run alone
// with --benchmark_filter=BM_Stage.
#include <benchmark/benchmark.h>

#include <functional>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "gvs/dsp/blur_analysis.hpp"
#include "gvs/dsp/dft.hpp"
#include "gvs/dsp/gvs_analysis.hpp"
#include "gvs/dsp/gvs_settings.hpp"
#include "gvs/dsp/phase_correlation.hpp"
#include "gvs/dsp/spectrum.hpp"
#include "gvs_bench_frames.hpp"

namespace gvs::bench {

namespace {

// Spectra are 1.5 MB each: a few frames are enough for the stages.
constexpr std::size_t kStageFrames = 8;

struct Inputs {
  cv::Size size;
  std::vector<cv::Mat> gray;      ///< CV_8U frames
  std::vector<cv::Mat> windowed;  ///< CV_32F frames, mean out (what WindowedSpectrum transforms)
  std::vector<cv::Mat> spectrum;  ///< CV_32FC2, WindowedSpectrum (Tukey)
};

const Inputs& inputs_of(const char* kind_name) {
  static std::vector<std::pair<std::string, Inputs>> cache;
  for (const auto& [name, in] : cache) {
    if (name == kind_name) return in;
  }
  const std::vector<dsp::FrameView>& frames = frames_of(kind_named(kind_name));
  Inputs in;
  in.size = frames.front().gray.size();
  dsp::WindowedSpectrum tukey(in.size);
  const cv::Mat window = dsp::spectrum_window(in.size, CV_32F);
  for (std::size_t i = 0; i < kStageFrames && i < frames.size(); ++i) {
    in.gray.push_back(frames[i].gray);
    cv::Mat f;
    frames[i].gray.convertTo(f, CV_32F);
    f -= cv::mean(f);
    in.windowed.push_back(f.mul(window));
    cv::Mat s;
    tukey.compute(frames[i].gray, s);
    in.spectrum.push_back(s);
  }
  cache.emplace_back(kind_name, std::move(in));
  return cache.back().second;
}

/// `step(i)` on input i, round and round.
void run_stage(benchmark::State& state, std::size_t n, const std::function<void(std::size_t)>& step) {
  std::size_t i = 0;
  for (auto _ : state) {
    step(i % n);
    ++i;
  }
}

void add(const char* stage, const char* kind, const std::function<void(benchmark::State&, const Inputs&)>& body) {
  const std::string name = std::string("BM_Stage/") + stage + "/" + kind;
  benchmark::RegisterBenchmark(name.c_str(), [body, kind](benchmark::State& state) {
    body(state, inputs_of(kind));
  })->Unit(benchmark::kMillisecond);
}

}  // namespace

void register_stage_benchmarks() {
  const dsp::GvsEstimatorSettings set;

  // --- the transforms, 512x384 ---
  add("fftw_r2c_measure", "blurred", [](benchmark::State& state, const Inputs& in) {
    FftwR2c r2c(in.size);
    r2c.load(in.gray.front());
    for (auto _ : state) r2c.run();
  });
  add("cv_dft_forward", "blurred", [](benchmark::State& state, const Inputs& in) {
    cv::Mat out(in.size, CV_32FC2);
    run_stage(state, in.windowed.size(), [&](std::size_t i) { cv::dft(in.windowed[i], out, cv::DFT_COMPLEX_OUTPUT); });
  });
  add("dft_plan_forward", "blurred", [](benchmark::State& state, const Inputs& in) {
    dsp::DftPlan plan(dsp::DftPlan::Direction::forward_real_to_complex);
    cv::Mat out;
    run_stage(state, in.windowed.size(), [&](std::size_t i) { plan.run(in.windowed[i], out); });
  });
  add("dft_plan_forward_half", "blurred", [](benchmark::State& state, const Inputs& in) {
    dsp::DftPlan plan(dsp::DftPlan::Direction::forward_real_to_half_complex);
    cv::Mat out;
    run_stage(state, in.windowed.size(), [&](std::size_t i) { plan.run(in.windowed[i], out); });
  });
  add("dft_plan_inverse", "blurred", [](benchmark::State& state, const Inputs& in) {
    dsp::DftPlan plan(dsp::DftPlan::Direction::inverse_complex_to_real);
    cv::Mat out;
    run_stage(state, in.spectrum.size(), [&](std::size_t i) { plan.run(in.spectrum[i], out); });
  });

  // --- spectra: window, mean and forward DFT (the half the estimator reads) ---
  constexpr auto kHalf = dsp::DftPlan::Direction::forward_real_to_half_complex;
  add("windowed_spectrum", "blurred", [](benchmark::State& state, const Inputs& in) {
    dsp::WindowedSpectrum tukey(in.size, dsp::kWindowTaper, kHalf);
    cv::Mat out;
    run_stage(state, in.gray.size(), [&](std::size_t i) { tukey.compute(in.gray[i], out); });
  });
  add("windowed_spectrum_pixel_pattern", "dark", [](benchmark::State& state, const Inputs& in) {
    dsp::WindowedSpectrum tukey(in.size, dsp::kWindowTaper, kHalf);
    const cv::Mat offsets(in.size, CV_32F, cv::Scalar(1.0));
    cv::Mat out;
    run_stage(state, in.gray.size(), [&](std::size_t i) { tukey.compute(in.gray[i], out, offsets); });
  });

  // --- frame pair: two half-window spectra and two phase correlations ---
  add("pair_half_spectra", "sharp_pair", [](benchmark::State& state, const Inputs& in) {
    dsp::PairWorkspace ws(in.size);
    run_stage(state, in.gray.size(), [&](std::size_t i) {
      ws.half_spectrum.compute(in.gray[i](ws.left), ws.current.left);
      ws.half_spectrum.compute(in.gray[i](ws.right), ws.current.right);
    });
  });
  add("pair_phase_correlation", "sharp_pair", [set](benchmark::State& state, const Inputs& in) {
    dsp::PairWorkspace ws(in.size);
    const std::size_t n = in.gray.size() - 1;
    std::vector<dsp::HalfSpectra> halves(in.gray.size());
    for (std::size_t i = 0; i < in.gray.size(); ++i) {
      ws.half_spectrum.compute(in.gray[i](ws.left), halves[i].left);
      ws.half_spectrum.compute(in.gray[i](ws.right), halves[i].right);
    }
    run_stage(state, n, [&](std::size_t i) {
      benchmark::DoNotOptimize(ws.correlator.correlate(halves[i].left, halves[i + 1].left, set.pair_exclude_px,
                                                       set.pair_max_shift_px));
      benchmark::DoNotOptimize(ws.correlator.correlate(halves[i].right, halves[i + 1].right, set.pair_exclude_px,
                                                       set.pair_max_shift_px));
    });
  });

  // --- one frame: passes over the power spectrum ---
  add("noise_floor", "blurred", [](benchmark::State& state, const Inputs& in) {
    const dsp::BlurAnalyzer blur(in.size);
    run_stage(state, in.spectrum.size(), [&](std::size_t i) { benchmark::DoNotOptimize(blur.noise_floor(in.spectrum[i])); });
  });
  add("ring_gain", "dark", [](benchmark::State& state, const Inputs& in) {
    const dsp::BlurAnalyzer blur(in.size);
    dsp::BlurAnalyzer::RingGain gain{};
    run_stage(state, in.spectrum.size(), [&](std::size_t i) { blur.ring_gain(in.spectrum[i], nullptr, 0.0, gain); });
  });
  add("streak_axis", "blurred", [](benchmark::State& state, const Inputs& in) {
    const dsp::BlurAnalyzer blur(in.size);
    run_stage(state, in.spectrum.size(), [&](std::size_t i) { benchmark::DoNotOptimize(blur.streak_axis(in.spectrum[i])); });
  });
  add("refine_axis", "blurred", [set](benchmark::State& state, const Inputs& in) {
    const dsp::BlurAnalyzer blur(in.size);
    run_stage(state, in.spectrum.size(), [&](std::size_t i) {
      const dsp::StreakAxis axis = blur.streak_axis(in.spectrum[i]);
      benchmark::DoNotOptimize(blur.refine_axis(in.spectrum[i], axis, set.refine_sigma, 2, true));
    });
  });
  add("streak_length", "strobed", [set](benchmark::State& state, const Inputs& in) {
    dsp::BlurAnalyzer blur(in.size);
    std::vector<dsp::StreakAxis> axes;
    for (const cv::Mat& s : in.spectrum) axes.push_back(blur.streak_axis(s));
    run_stage(state, in.spectrum.size(), [&](std::size_t i) {
      benchmark::DoNotOptimize(blur.streak_length(in.spectrum[i], axes[i], set.min_streak_search_px, 300.0));
    });
  });
  add("double_image", "double_pulse", [](benchmark::State& state, const Inputs& in) {
    dsp::BlurAnalyzer blur(in.size);
    run_stage(state, in.spectrum.size(), [&](std::size_t i) { benchmark::DoNotOptimize(blur.double_image(in.spectrum[i], 4.0, 200.0)); });
  });
  add("double_image_asymmetry", "double_pulse", [](benchmark::State& state, const Inputs& in) {
    dsp::BlurAnalyzer blur(in.size);
    std::vector<dsp::DoubleImage> pairs;
    for (const cv::Mat& s : in.spectrum) pairs.push_back(blur.double_image(s, 4.0, 200.0));
    run_stage(state, in.gray.size(), [&](std::size_t i) { dsp::double_image_asymmetry(in.gray[i], pairs[i]); });
  });
}

}  // namespace gvs::bench
