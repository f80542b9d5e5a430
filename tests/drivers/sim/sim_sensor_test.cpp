// Sensor and light: light levels hit their targets, closed-loop exposure
// changes photons (and noise) physically while the gain keeps the mean,
// fixed-pattern noise is fixed, runs are deterministic per seed.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include <opencv2/core/utility.hpp>

#include "gvs/drivers/simulator.hpp"
#include "sim_test_util.hpp"

namespace gvs::drivers::sim::test {
namespace {

double saturated_fraction(const cv::Mat& gray) {
  return static_cast<double>(cv::countNonZero(gray >= 255)) / static_cast<double>(gray.total());
}

SimFrame frame(Simulator& sim, std::int64_t index) {
  SimFrame f;
  sim.render(index, sim.exposure(), f);
  return f;
}

TEST(SimSensor, NormalLightGivesMeanGreyAbout110) {
  for (const char* scenario : {"stop", "sine", "const"}) {
    SimulatorConfig c;
    c.scenario = scenario;
    Simulator sim(c);
    for (const std::int64_t i : {0, 40, 200}) {
      const double mean = cv::mean(frame(sim, i).gray)[0];
      EXPECT_NEAR(mean, 110.0, 12.0) << scenario << " frame " << i;
    }
  }
}

TEST(SimSensor, UnderexposedGivesMeanGreyAbout10) {
  SimulatorConfig c;
  c.scenario = "crawl";
  c.light = LightLevel::under;
  Simulator sim(c);
  for (const std::int64_t i : {0, 100}) {
    const double mean = cv::mean(frame(sim, i).gray)[0];
    EXPECT_NEAR(mean, 10.0, 2.5) << "frame " << i;
  }
}

TEST(SimSensor, OverexposedSaturatesAbout15Percent) {
  SimulatorConfig c;
  c.scenario = "crawl";
  c.light = LightLevel::over;
  Simulator sim(c);
  for (const std::int64_t i : {0, 100}) {
    const double sat = saturated_fraction(frame(sim, i).gray);
    EXPECT_GT(sat, 0.08) << "frame " << i;
    EXPECT_LT(sat, 0.25) << "frame " << i;
  }
  SimulatorConfig n;
  n.scenario = "crawl";
  Simulator normal(n);
  EXPECT_LT(saturated_fraction(frame(normal, 0).gray), 0.02);
}

TEST(SimSensor, LightFallsOffTowardsTheCorners) {
  // Average over many frames of a moving texture: what remains is the light.
  SimulatorConfig c;
  Simulator sim(c, constant_motion_scenario(3.0, 0.0));
  cv::Mat sum = cv::Mat::zeros(384, 512, CV_64F);
  for (int i = 0; i < 12; ++i) {
    cv::Mat f;
    frame(sim, i).gray.convertTo(f, CV_64F);
    sum += f;
  }
  const double centre = cv::mean(sum(cv::Rect(226, 162, 60, 60)))[0];
  const double corner = cv::mean(sum(cv::Rect(0, 0, 24, 24)))[0];
  const double black = c.sensor.black_level_dn * 12;
  EXPECT_NEAR((corner - black) / (centre - black), 1.0 - c.sensor.corner_falloff, 0.1);
}

/// Temporal noise: a noisy frame minus the same frame rendered noise-free.
double temporal_noise(const core::ExposurePlan& plan) {
  SimulatorConfig noisy;
  noisy.sensor.fixed_pattern_noise = false;
  SimulatorConfig clean = noisy;
  clean.sensor.shot_and_read_noise = false;
  Simulator a(noisy, constant_motion_scenario(0.0, 0.0));
  Simulator b(clean, constant_motion_scenario(0.0, 0.0));
  cv::Mat fa, fb;
  render(a, 1, plan).convertTo(fa, CV_64F);
  render(b, 1, plan).convertTo(fb, CV_64F);
  cv::Scalar mu, sd;
  cv::meanStdDev(fa - fb, mu, sd);
  return sd[0];
}

TEST(SimSensor, ClosedLoopExposureChangesPhotonsAndGainKeepsTheMean) {
  Simulator sim(SimulatorConfig{}, constant_motion_scenario(0.0, 0.0));
  SimFrame f;
  ASSERT_TRUE(sim.next(f));
  const double mean_continuous = cv::mean(f.gray)[0];
  // A 100 us strobe with the LED overdriven 10x: 1/3 of the photons, 3x the gain.
  sim.set_exposure(strobe(0, 100));
  ASSERT_TRUE(sim.next(f));
  EXPECT_EQ(f.record.exposure.pulse_count, 1U);
  EXPECT_DOUBLE_EQ(f.record.exposure.pulses[0].duration_us, 100.0);
  EXPECT_NEAR(cv::mean(f.gray)[0], mean_continuous, 3.0);
  // Shot noise grows as 1/sqrt(photons) relative to the signal: sqrt(3) more DN.
  const double n_cont = temporal_noise(continuous(3000));
  const double n_strobe = temporal_noise(strobe(0, 100));
  EXPECT_NEAR(n_strobe / n_cont, std::sqrt(3.0), 0.25) << n_cont << " " << n_strobe;
  // Beyond the gain range (a 2 us strobe needs 150x) the frame gets dark.
  sim.set_exposure(strobe(0, 2));
  ASSERT_TRUE(sim.next(f));
  EXPECT_LT(cv::mean(f.gray)[0], 30.0);
}

TEST(SimSensor, LongStrobesKeepTheEnergyOfARatedPulse) {
  // Overdriven 10x up to 200 us; a longer pulse keeps that pulse's energy
  // (2000 us of continuous light) and is never dimmer than continuous light.
  // The gain keeps the mean, so the light shows in the shot noise (~1/sqrt).
  const double n_rated = temporal_noise(strobe(0, 200));
  EXPECT_NEAR(temporal_noise(strobe(0, 800)) / n_rated, 1.0, 0.08);
  EXPECT_NEAR(temporal_noise(strobe(0, 100)) / n_rated, std::sqrt(2.0), 0.15);
  EXPECT_NEAR(temporal_noise(strobe(0, 2800)) / temporal_noise(continuous(2800)), 1.0, 0.08);
}

TEST(SimSensor, ImpossibleExposurePlansAreRejected) {
  Simulator sim(SimulatorConfig{}, constant_motion_scenario(0.0, 0.0));
  EXPECT_THROW(sim.set_exposure(continuous(0.0)), std::invalid_argument);
  EXPECT_THROW(sim.set_exposure(continuous(20000.0)), std::invalid_argument);  // > 1/60 s
  EXPECT_THROW(sim.set_exposure(strobe(2990, 20)), std::invalid_argument);     // ends after exposure
  core::ExposurePlan p = continuous(3000);
  p.pulse_count = 2;
  p.pulses[0] = {100, 50};
  p.pulses[1] = {120, 50};  // overlaps
  EXPECT_THROW(sim.set_exposure(p), std::invalid_argument);
  EXPECT_NO_THROW(sim.set_exposure(strobe(2980, 20)));
}

/// Height of the phase-correlation surface of a and b at zero shift, in
/// standard deviations of the surface.
double zero_shift_peak_sigma(const cv::Mat& a, const cv::Mat& b) {
  cv::Mat fa, fb, A, B, R, surface;
  a.convertTo(fa, CV_64F);
  b.convertTo(fb, CV_64F);
  fa -= cv::mean(fa)[0];
  fb -= cv::mean(fb)[0];
  cv::dft(fa, A, cv::DFT_COMPLEX_OUTPUT);
  cv::dft(fb, B, cv::DFT_COMPLEX_OUTPUT);
  cv::mulSpectrums(A, B, R, 0, true);
  std::vector<cv::Mat> ch;
  cv::split(R, ch);
  cv::Mat mag;
  cv::magnitude(ch[0], ch[1], mag);
  mag += 1e-9;
  ch[0] /= mag;
  ch[1] /= mag;
  cv::merge(ch, R);
  cv::dft(R, surface, cv::DFT_INVERSE | cv::DFT_REAL_OUTPUT | cv::DFT_SCALE);
  cv::Scalar mu, sd;
  cv::meanStdDev(surface, mu, sd);
  return (surface.at<double>(0, 0) - mu[0]) / sd[0];
}

TEST(SimSensor, FixedPatternNoisePutsAFalsePeakAtZeroShift) {
  // Two frames of different ground (83 mm apart): only the sensor's fixed
  // pattern is common to both, so their correlation peaks at zero shift.
  auto peak = [](bool fpn) {
    SimulatorConfig c;
    c.sensor.fixed_pattern_noise = fpn;
    c.sensor.light_falloff = false;
    Simulator sim(c, constant_motion_scenario(5.0, 0.0));
    return zero_shift_peak_sigma(render(sim, 0, strobe(0, 20)), render(sim, 1, strobe(0, 20)));
  };
  const double with = peak(true);
  const double without = peak(false);
  EXPECT_GT(with, 8.0);
  EXPECT_LT(std::abs(without), 5.0);
}

TEST(SimSensor, FixedPatternIsFixedPerSensorSeed) {
  // Dark frames (2 us strobe, beyond the gain range): offsets dominate.
  auto dark = [](std::uint64_t scene_seed, std::uint64_t sensor_seed) {
    SimulatorConfig c;
    c.seed = scene_seed;
    c.sensor_seed = sensor_seed;
    c.sensor.shot_and_read_noise = false;
    c.light = LightLevel::under;
    Simulator sim(c, constant_motion_scenario(0.0, 0.0));
    cv::Mat f;
    render(sim, 0, strobe(0, 1)).convertTo(f, CV_64F);
    return f;
  };
  cv::Mat a = dark(1, 7), b = dark(2, 7), d = dark(1, 8);
  auto corr = [](const cv::Mat& x, const cv::Mat& y) {
    cv::Mat xm = x - cv::mean(x)[0], ym = y - cv::mean(y)[0];
    return xm.dot(ym) / std::sqrt(xm.dot(xm) * ym.dot(ym));
  };
  EXPECT_GT(corr(a, b), 0.5);  // same sensor, different ground
  EXPECT_LT(corr(a, d), corr(a, b) - 0.3);  // other sensor
}

TEST(SimSensor, RunsAreDeterministicPerSeed) {
  // No light falloff and no fixed pattern here: both are common to any two
  // frames and would correlate them (temporal noise stays on).
  SimulatorConfig c = geometry_config(1);
  c.scenario = "skidpad";
  Simulator a(c), b(c);
  c.seed = 2;
  Simulator other(c);
  for (int i = 0; i < 3; ++i) {
    SimFrame fa, fb, fo;
    ASSERT_TRUE(a.next(fa));
    ASSERT_TRUE(b.next(fb));
    ASSERT_TRUE(other.next(fo));
    EXPECT_EQ(cv::norm(fa.gray, fb.gray, cv::NORM_INF), 0.0) << "frame " << i;
    EXPECT_EQ(fa.truth.t_ns, fb.truth.t_ns);
    cv::Mat x, y;
    fa.gray.convertTo(x, CV_64F);
    fo.gray.convertTo(y, CV_64F);
    x -= cv::mean(x)[0];
    y -= cv::mean(y)[0];
    EXPECT_LT(std::abs(x.dot(y) / std::sqrt(x.dot(x) * y.dot(y))), 0.3) << "frame " << i;
    EXPECT_EQ(fa.truth.vx_mps, fo.truth.vx_mps);  // same motion, other asphalt
  }
}

TEST(SimSensor, FramesDoNotDependOnTheNumberOfThreads) {
  SimulatorConfig c;
  c.scenario = "spin";
  Simulator sim(c);
  const int threads = cv::getNumThreads();
  SimFrame a, b;
  cv::setNumThreads(1);
  sim.render(100, sim.exposure(), a);
  cv::setNumThreads(std::max(2, threads));
  sim.render(100, sim.exposure(), b);
  cv::setNumThreads(threads);
  EXPECT_EQ(cv::norm(a.gray, b.gray, cv::NORM_INF), 0.0);
}

TEST(SimSensor, StandingFramesReuseTheRasterWithoutChangingTheImage) {
  SimulatorConfig c;
  c.scenario = "stop";
  Simulator warm(c);
  Simulator fresh(c);
  SimFrame a, b;
  warm.render(4, warm.exposure(), a);
  warm.render(5, warm.exposure(), a);  // same raster as frame 4: reused
  EXPECT_EQ(warm.last_render_stats().texture_ms, 0.0);
  fresh.render(300, fresh.exposure(), b);  // 5 m/s: another raster
  fresh.render(5, fresh.exposure(), b);    // so this one is rendered afresh
  EXPECT_GT(fresh.last_render_stats().texture_ms, 0.0);
  EXPECT_EQ(cv::norm(a.gray, b.gray, cv::NORM_INF), 0.0);
}

}  // namespace
}  // namespace gvs::drivers::sim::test
