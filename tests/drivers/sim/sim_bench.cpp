// Simulator render cost per frame (docs/simulator.md, "Speed").
//   build/sim/tests/drivers/sim/gvs_sim_bench --benchmark_min_time=2
// "Time" is wall time per frame, "CPU" the CPU time of all threads per frame.
#include <benchmark/benchmark.h>

#include "gvs/drivers/simulator.hpp"

namespace {

using gvs::drivers::SimFrame;
using gvs::drivers::Simulator;
using gvs::drivers::SimulatorConfig;

void report(benchmark::State& state, const Simulator& sim) {
  const auto& s = sim.last_render_stats();
  state.counters["raster_Mpx"] = static_cast<double>(s.raster_rows) * s.raster_cols / 1e6;
  state.counters["texture_ms"] = s.texture_ms;
  state.counters["psf_ms"] = s.psf_ms;
  state.counters["integrate_ms"] = s.integrate_ms;
  state.counters["sensor_ms"] = s.sensor_ms;
  state.counters["box_filtered"] = s.box_filtered ? 1.0 : 0.0;
}

/// Constant speed (km/h) forward at 10 deg, continuous 3 ms exposure.
void BM_ConstantSpeed(benchmark::State& state) {
  const double kmh = static_cast<double>(state.range(0));
  const double v = kmh / 3.6;
  Simulator sim(SimulatorConfig{},
                gvs::drivers::sim::constant_motion_scenario(v * 0.9848, v * 0.1736, 0.0, 100.0));
  SimFrame f;
  std::int64_t i = 0;
  for (auto _ : state) {
    sim.render(i++, sim.exposure(), f);
    benchmark::DoNotOptimize(f.gray.data);
  }
  report(state, sim);
}
BENCHMARK(BM_ConstantSpeed)->Arg(0)->Arg(10)->Arg(60)->Arg(140)->Arg(250)->Unit(benchmark::kMillisecond)->MeasureProcessCPUTime()->UseRealTime();

/// Short double strobe at 140 km/h (sharp double image).
void BM_DoubleStrobe140(benchmark::State& state) {
  Simulator sim(SimulatorConfig{}, gvs::drivers::sim::constant_motion_scenario(140 / 3.6, 0.0, 0.0, 100.0));
  gvs::core::ExposurePlan p;
  p.exposure_us = 3000;
  p.pulse_count = 2;
  p.pulses[0] = {0, 20};
  p.pulses[1] = {400, 20};
  SimFrame f;
  std::int64_t i = 0;
  for (auto _ : state) {
    sim.render(i++, p, f);
    benchmark::DoNotOptimize(f.gray.data);
  }
  report(state, sim);
}
BENCHMARK(BM_DoubleStrobe140)->Unit(benchmark::kMillisecond)->MeasureProcessCPUTime()->UseRealTime();

/// A built-in scenario, frame after frame (rotation: spin, skidpad).
void BM_Scenario(benchmark::State& state, const char* name) {
  SimulatorConfig c;
  c.scenario = name;
  c.loop = true;
  Simulator sim(c);
  SimFrame f;
  for (auto _ : state) {
    sim.next(f);
    benchmark::DoNotOptimize(f.gray.data);
  }
  report(state, sim);
}
BENCHMARK_CAPTURE(BM_Scenario, sine, "sine")->Unit(benchmark::kMillisecond)->MeasureProcessCPUTime()->UseRealTime();
BENCHMARK_CAPTURE(BM_Scenario, skidpad, "skidpad")->Unit(benchmark::kMillisecond)->MeasureProcessCPUTime()->UseRealTime();
BENCHMARK_CAPTURE(BM_Scenario, spin, "spin")->Unit(benchmark::kMillisecond)->MeasureProcessCPUTime()->UseRealTime();

/// gvsd's live `sim:sine` camera: argument 0 the exact render of the
/// periodic tile, 1 the live fast render (SimulatorConfig::live_fast_render,
/// what gvsd uses); second argument the plan: 0 its steady double pulse at
/// 60 km/h (two 12 us pulses 600 us apart: 2 px of streak each, 100 px
/// apart), 1 the continuous 3 ms of its first frames (500 px of streak).
void BM_LiveSine(benchmark::State& state) {
  SimulatorConfig c;
  c.scenario = "sine";
  c.loop = true;
  c.periodic_texture = true;
  c.live_fast_render = state.range(0) != 0;
  Simulator sim(c);
  gvs::core::ExposurePlan p;
  p.exposure_us = 3000;
  if (state.range(1) == 0) {
    p.exposure_us = 612;
    p.pulse_count = 2;
    p.pulses[0] = {0, 12};
    p.pulses[1] = {600, 12};
  }
  SimFrame f;
  std::int64_t i = 0;
  for (auto _ : state) {
    sim.render(i++, p, f);
    benchmark::DoNotOptimize(f.gray.data);
  }
  report(state, sim);
}
BENCHMARK(BM_LiveSine)
    ->ArgsProduct({{0, 1}, {0, 1}})
    ->ArgNames({"fast", "continuous"})
    ->Unit(benchmark::kMillisecond)
    ->MeasureProcessCPUTime()
    ->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
