// The gvs estimator on gvsd's live simulated camera (SimulatorConfig::
// live_fast_render: periodic tile with the PSF baked in, pixel-pitch raster,
// box-filter path integrals, table noise; docs/simulator.md, "Live source"):
// in closed loop with the daemon's default double pulse it must measure the
// true speed and direction as it does on the exact render.
#include <gtest/gtest.h>

#include "gvs_sim_eval.hpp"

namespace gvs::test {
namespace {

drivers::SimulatorConfig live_sine(bool fast) {
  drivers::SimulatorConfig c;
  c.scenario = "sine";
  c.seconds = 1.7;
  c.seed = 3;
  c.periodic_texture = true;  // what gvsd's sim: source renders
  c.live_fast_render = fast;
  return c;
}

TEST(LiveSimulatedCamera, DoublePulseAt60KmhMeasuresTheTrueVelocity) {
  // As GvsAccuracy.DoublePulseAt60KmhClosedLoop: cold start from 3 ms
  // continuous, the first 0.2 s excluded.
  const RunScore fast = run_and_score(live_sine(true), dsp::ExposureMode::double_pulse, 0.2);
  print_score("live fast render, sine double-pulse 1.7 s", fast);
  const RunScore exact = run_and_score(live_sine(false), dsp::ExposureMode::double_pulse, 0.2);
  print_score("exact render of the same periodic ground", exact);
  const BandScore& b = fast.bands[3];  // 60-140 km/h
  ASSERT_GT(b.frames, 70);
  EXPECT_GE(b.dir_coverage(), 0.99);
  EXPECT_LE(b.dir_rms(), 0.1);
  EXPECT_LE(b.dir_max, 0.5);
  EXPECT_GE(b.speed_coverage(), 0.99);
  EXPECT_LE(b.speed_rms(), 0.0025);
  EXPECT_EQ(fast.confident_bad, 0);
  // No worse than the exact render of the same ground by more than a little.
  const BandScore& e = exact.bands[3];
  EXPECT_LE(b.dir_rms(), e.dir_rms() + 0.03);
  EXPECT_LE(b.speed_rms(), e.speed_rms() + 0.001);
}

}  // namespace
}  // namespace gvs::test
