// The "gvs" estimator on synthetic sequences (gvs_synth.hpp): signs, mount
// yaw, standstill with fixed-pattern noise, yaw rate, sign continuity into
// single-frame blur, double pulse, frames with nothing to measure.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>
#include <vector>

#include "gvs/dsp/estimator.hpp"
#include "gvs/dsp/vocabulary.hpp"
#include "gvs/dsp/gvs_estimator.hpp"
#include "gvs_synth.hpp"

namespace gvs::dsp {
namespace {

constexpr double kFramePeriodUs = 1e6 / 60.0;

const cv::Mat& texture() {
  static const cv::Mat tex = test::make_texture(1024, 11);
  return tex;
}

/// A car moving at constant vehicle velocity (m/s) and yaw rate (deg/s),
/// filmed with `exposure` (pulses in us from the frame start).
struct SynthRun {
  CameraGeometry cam;
  Vec2 v_mps{1.0, 0.0};
  double yaw_dps = 0.0;
  ExposurePlan exposure;
  test::Sensor sensor;
  const cv::Mat* ground = &texture();

  [[nodiscard]] FrameView frame(int i, cv::Mat& storage) const {
    // Image velocity in px per microsecond; ground position at the frame start.
    const Vec2 px_per_us = velocity_to_image_shift(v_mps, 1e-6, cam);
    const double omega_per_us = deg_to_rad(yaw_dps) * 1e-6;
    const double t0 = i * kFramePeriodUs;
    std::vector<test::Pulse> pulses;
    if (exposure.pulse_count == 0) {
      pulses.push_back({0.0, exposure.exposure_us, 1.0});
    } else {
      for (std::size_t k = 0; k < exposure.pulse_count; ++k) {
        pulses.push_back({exposure.pulses[k].start_us, exposure.pulses[k].duration_us, 1.0});
      }
    }
    storage = test::render_frame(*ground, {cam.width_px, cam.height_px}, px_per_us.x * t0,
                                 px_per_us.y * t0, omega_per_us * t0, px_per_us.x, px_per_us.y,
                                 omega_per_us, pulses, sensor, 100 + static_cast<std::uint64_t>(i));
    FrameView f;
    f.gray = storage;
    f.index = i;
    f.t_ns = static_cast<std::int64_t>(std::llround(t0 * 1000.0));
    f.exposure = exposure;
    return f;
  }
};

std::unique_ptr<VelocityEstimator> make_gvs(const CameraGeometry& cam) {
  EstimatorConfig cfg;
  cfg.method = "gvs";
  cfg.camera = cam;
  return make_estimator(cfg);
}

double dir_error(const VelocityEstimate& e, Vec2 v) { return wrap_deg(e.direction_deg - direction_deg(v)); }

TEST(GvsEstimator, IsRegisteredInTheFactory) {
  const std::vector<std::string> names = estimator_names();
  EXPECT_NE(std::find(names.begin(), names.end(), "gvs"), names.end());
  EXPECT_NE(make_gvs(CameraGeometry{}), nullptr);
}

// This program links gvs::dsp alone, as gvsd does: the thesis's ORB methods
// are not there, and asking for one says where they are.
TEST(GvsEstimator, WithoutDspOrbTheOrbMethodsAreAbsentAndSaySo) {
  const std::vector<std::string> names = estimator_names();
  EXPECT_EQ(names, (std::vector<std::string>{"gvs", "thesis-fft", "thesis-laplacian"}));
  for (const char* method : {"thesis", "thesis-orb"}) {
    EstimatorConfig cfg;
    cfg.method = method;
    try {
      (void)make_estimator(cfg);
      ADD_FAILURE() << method << " was made without gvs::dsp_orb";
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find("the desk tool `gvs` has it"), std::string::npos) << e.what();
    }
  }
  EstimatorConfig unknown;
  unknown.method = "magic";
  try {
    (void)make_estimator(unknown);
    ADD_FAILURE() << "magic was made";
  } catch (const std::invalid_argument& e) {
    EXPECT_EQ(std::string(e.what()).find("desk tool"), std::string::npos) << e.what();
  }
}

struct PairCase {
  double vx;
  double vy;
  double mount_yaw_deg;
};

class GvsPair : public ::testing::TestWithParam<PairCase> {};

TEST_P(GvsPair, SlowMotionGivesSignedVelocityFromFramePairs) {
  const PairCase c = GetParam();
  SynthRun run;
  run.cam.mount_yaw_deg = c.mount_yaw_deg;
  run.v_mps = {c.vx, c.vy};
  auto est = make_gvs(run.cam);
  cv::Mat img;
  for (int i = 0; i < 5; ++i) {
    const FrameView f = run.frame(i, img);
    const VelocityEstimate e = est->estimate(f);
    EXPECT_EQ(e.t_ns, f.t_ns + 1500000);  // mid-exposure of a 3 ms exposure
    if (i == 0) continue;  // no pair yet
    EXPECT_EQ(e.method, Method::pair) << "frame " << i;
    ASSERT_TRUE(e.has_speed && e.has_direction) << "frame " << i;
    EXPECT_NEAR(e.speed_mps, std::hypot(c.vx, c.vy), 0.01 * std::hypot(c.vx, c.vy));
    EXPECT_NEAR(dir_error(e, run.v_mps), 0.0, 0.3);
    EXPECT_NEAR(e.vx_mps, c.vx, 0.02);
    EXPECT_NEAR(e.vy_mps, c.vy, 0.02);
    EXPECT_TRUE(e.has_yaw_rate);
    EXPECT_NEAR(e.yaw_rate_dps, 0.0, 3.0);
    EXPECT_GT(e.quality, 0.5);
  }
}

INSTANTIATE_TEST_SUITE_P(Directions, GvsPair,
                         ::testing::Values(PairCase{0.8, 0.1, 0.0}, PairCase{-0.5, 0.0, 0.0},
                                           PairCase{0.3, -0.6, 0.0}, PairCase{0.8, 0.1, 12.0},
                                           PairCase{-0.4, 0.4, -30.0}));

TEST(GvsEstimator, YawRateFromTheTwoHalves) {
  // 0.6 m/s turning at 20 deg/s (a 1.7 m radius, full lock at a crawl):
  // 18 px streaks, each half's peak significance 42-51, a yaw rate's
  // standard error of 2.0-2.3 deg/s (pair_max_yaw_rate_sigma_dps: 3).
  SynthRun run;
  run.v_mps = {0.6, 0.0};
  run.yaw_dps = 20.0;
  auto est = make_gvs(run.cam);
  cv::Mat img;
  for (int i = 0; i < 5; ++i) {
    const VelocityEstimate e = est->estimate(run.frame(i, img));
    if (i == 0) continue;
    ASSERT_TRUE(e.has_yaw_rate) << "frame " << i;
    EXPECT_NEAR(e.yaw_rate_dps, 20.0, 4.0) << "frame " << i;
  }
}

TEST(GvsEstimator, StandstillIsZeroSpeedWithoutDirectionDespiteFixedPatternNoise) {
  SynthRun run;
  run.v_mps = {0.0, 0.0};
  run.sensor.fpn_grey = 4.0;
  auto est = make_gvs(run.cam);
  cv::Mat img;
  for (int i = 0; i < 4; ++i) {
    const VelocityEstimate e = est->estimate(run.frame(i, img));
    if (i == 0) continue;
    EXPECT_EQ(e.method, Method::still);
    EXPECT_TRUE(e.has_speed);
    EXPECT_LT(e.speed_mps, 0.01);
    EXPECT_FALSE(e.has_direction);
    EXPECT_GT(e.quality, 0.5);
  }
}

TEST(GvsEstimator, BackwardsStaysBackwardsWhenFramesStopOverlapping) {
  // Reversing slowly (pairs give the sign), then frames 4.. are fast: only
  // the streak is left, whose sign must come from continuity.
  SynthRun slow;
  slow.v_mps = {-0.6, -0.05};
  auto est = make_gvs(slow.cam);
  cv::Mat img;
  for (int i = 0; i < 3; ++i) {
    const VelocityEstimate e = est->estimate(slow.frame(i, img));
    if (i > 0) {
      EXPECT_EQ(e.method, Method::pair);
    }
  }
  SynthRun fast = slow;
  fast.v_mps = {-6.0, -0.5};           // 21.7 km/h: 360 px between frames
  fast.exposure.exposure_us = 1000.0;  // 60 px streak: measurable
  for (int i = 3; i < 9; ++i) {
    const VelocityEstimate e = est->estimate(fast.frame(i, img));
    EXPECT_TRUE(e.method == Method::blur_cont || e.method == Method::streak_cont) << "frame " << i << " " << e.method;
    ASSERT_TRUE(e.has_direction);
    EXPECT_NEAR(dir_error(e, fast.v_mps), 0.0, 0.5) << "frame " << i;
    // The jump 0.6 -> 6 m/s in one frame is not physical: the streak-length
    // search stays gated around the last speed for 3 frames (no speed rather
    // than a wrong one), then searches everywhere and finds it.
    if (i >= 6) {
      ASSERT_TRUE(e.has_speed) << "frame " << i;
      EXPECT_NEAR(e.speed_mps, std::hypot(-6.0, -0.5), 0.02 * 6.0) << "frame " << i;
    }
  }
}

TEST(GvsEstimator, WithoutHistoryASingleBlurredFrameAssumesForwardAndSaysSo) {
  SynthRun run;
  run.v_mps = {-8.0, 1.0};
  run.exposure.exposure_us = 600.0;  // 48 px streak
  auto est = make_gvs(run.cam);
  cv::Mat img;
  const VelocityEstimate e = est->estimate(run.frame(0, img));
  EXPECT_EQ(e.method, Method::blur_fwd);
  ASSERT_TRUE(e.has_direction);
  EXPECT_NEAR(dir_error(e, {8.0, -1.0}), 0.0, 0.5);  // the forward reading of the axis
  EXPECT_LT(e.quality, 0.5);
}

TEST(GvsEstimator, DoublePulseMeasuresTheDisplacement) {
  SynthRun run;
  run.v_mps = {30.0, 2.0};  // 108 km/h
  run.exposure.pulse_count = 2;
  run.exposure.pulses[0] = {0.0, 3.0};
  run.exposure.pulses[1] = {300.0, 3.0};
  run.exposure.exposure_us = 303.0;
  auto est = make_gvs(run.cam);
  cv::Mat img;
  for (int i = 0; i < 4; ++i) {
    const VelocityEstimate e = est->estimate(run.frame(i, img));
    EXPECT_TRUE(e.method == Method::dpiv_cont || e.method == Method::dpiv_energy || e.method == Method::dpiv_fwd)
        << e.method;
    ASSERT_TRUE(e.has_speed && e.has_direction);
    EXPECT_NEAR(e.speed_mps, std::hypot(30.0, 2.0), 0.005 * 30.0);
    EXPECT_NEAR(dir_error(e, run.v_mps), 0.0, 0.1);
  }
}

TEST(GvsEstimator, UnequalPulseEnergiesDecideTheSignWithoutHistory) {
  SynthRun run;
  run.v_mps = {-25.0, 3.0};  // backwards: the forward prior would be wrong
  run.exposure.pulse_count = 2;
  run.exposure.pulses[0] = {0.0, 4.0};
  run.exposure.pulses[1] = {300.0, 2.0};  // half the energy
  run.exposure.exposure_us = 302.0;
  auto est = make_gvs(run.cam);
  cv::Mat img;
  const VelocityEstimate e = est->estimate(run.frame(0, img));
  EXPECT_EQ(e.method, Method::dpiv_energy);
  ASSERT_TRUE(e.has_direction);
  EXPECT_NEAR(dir_error(e, run.v_mps), 0.0, 0.2);
}

TEST(GvsEstimator, NothingToMeasureGivesQualityZeroAndTheReason) {
  auto est = make_gvs(CameraGeometry{});
  FrameView f;
  f.gray = cv::Mat(384, 512, CV_8UC1, cv::Scalar(0));
  VelocityEstimate e = est->estimate(f);
  EXPECT_EQ(e.method, Method::dark);
  EXPECT_EQ(e.quality, 0.0);
  EXPECT_FALSE(e.has_speed || e.has_direction || e.has_yaw_rate);
  f.gray = cv::Mat(384, 512, CV_8UC1, cv::Scalar(255));
  f.index = 1;
  EXPECT_EQ(est->estimate(f).method, Method::saturated);
  f.gray = cv::Mat(100, 100, CV_8UC1, cv::Scalar(100));
  f.index = 2;
  e = est->estimate(f);
  EXPECT_EQ(e.method, Method::bad_frame);
  EXPECT_EQ(e.quality, 0.0);
}

TEST(GvsEstimator, FreshNoiseWithoutTextureIsNotAMotion) {
  // Every frame new random noise: no texture, nothing moves. Whatever the
  // method says, it must not claim a speed or direction with quality.
  auto est = make_gvs(CameraGeometry{});
  cv::Mat noise(384, 512, CV_8UC1);
  for (int i = 0; i < 5; ++i) {
    cv::RNG rng(static_cast<std::uint64_t>(500 + i));
    rng.fill(noise, cv::RNG::NORMAL, 100.0, 3.0);
    FrameView f;
    f.gray = noise;
    f.index = i;
    f.t_ns = static_cast<std::int64_t>(i * kFramePeriodUs * 1000.0);
    const VelocityEstimate e = est->estimate(f);
    EXPECT_EQ(e.quality, 0.0) << "frame " << i << " " << e.method;
    EXPECT_FALSE(e.has_direction) << "frame " << i;
  }
}


TEST(GvsEstimator, OnlyTheSensorsFixedPatternIsNotAStandstill) {
  // Texture smeared flat by a streak far longer than the frame (under-exposed
  // at speed) leaves a uniform frame plus the sensor's fixed pattern, which
  // repeats from frame to frame like a standstill. It must not read as one:
  // a speed of 0 at racing speed would be a lie.
  SynthRun run;
  run.v_mps = {0.0, 0.0};
  run.sensor.contrast_grey = 0.0;  // no texture at all
  run.sensor.mean_grey = 12.0;
  run.sensor.noise_grey = 0.5;
  run.sensor.fpn_grey = 2.5;
  auto est = make_gvs(run.cam);
  cv::Mat img;
  for (int i = 0; i < 5; ++i) {
    const VelocityEstimate e = est->estimate(run.frame(i, img));
    EXPECT_NE(e.method, Method::still) << "frame " << i;
    EXPECT_FALSE(e.has_speed) << "frame " << i << " " << e.method;
  }
}

TEST(GvsEstimator, DarkFramesAtSpeedGiveTheDirectionOnceThePatternIsLearnt) {
  // Under-exposed at 60 km/h: streaks of most of the frame leave a texture
  // of a few tenths of a grey level, below the sensor's fixed pattern (2 grey
  // levels per pixel, the same in every frame). With the pattern in, the
  // spectrum shows little but it; learnt from a few frames of moving ground
  // and taken out, it leaves the direction. (A 256 x 192 frame and a 1 ms
  // exposure, 167 px streaks: the synthetic renderer's cost grows with both.)
  SynthRun run;
  run.cam.width_px = 256;
  run.cam.height_px = 192;
  run.v_mps = {16.7, 1.5};
  run.exposure.exposure_us = 1000.0;
  run.sensor.mean_grey = 10.0;
  run.sensor.contrast_grey = 3.0;
  run.sensor.noise_grey = 0.5;
  auto est = make_gvs(run.cam);
  cv::Mat img;
  int with_direction = 0;
  double worst_deg = 0.0;
  for (int i = 0; i < 12; ++i) {
    const VelocityEstimate e = est->estimate(run.frame(i, img));
    std::printf("frame %d: %s q %.2f dir %s%.2f deg\n", i, method_word(e.method), e.quality, e.has_direction ? "" : "(none) ",
                e.has_direction ? dir_error(e, run.v_mps) : 0.0);
    if (i == 0) {
      // Nothing learnt yet: no direction rather than the pattern's.
      EXPECT_FALSE(e.has_direction) << e.method;
      EXPECT_EQ(e.quality, 0.0);
    }
    if (i < 3) continue;  // the pattern is used from two frames after the first
    EXPECT_FALSE(e.has_speed) << "frame " << i;  // far too long to measure
    if (!e.has_direction) continue;
    ++with_direction;
    worst_deg = std::max(worst_deg, std::abs(dir_error(e, run.v_mps)));
  }
  EXPECT_EQ(with_direction, 9);
  EXPECT_LE(worst_deg, 0.5);
}

TEST(GvsEstimator, AStreakTooShortForADirectionGivesNone) {
  // 25 m/s under a 12 us strobe: a 3 px streak. Frames do not overlap, so one
  // frame must carry the answer, and its spectrum is barely elongated: no
  // direction (quality 0, "short-streak"): on asphalt, streaks of 1-9 px
  // read 6-25 deg off (docs/estimator.md, "Short streaks, faint streaks").
  SynthRun run;
  run.v_mps = {25.0, 3.0};
  run.exposure.exposure_us = 12.0;
  auto est = make_gvs(run.cam);
  cv::Mat img;
  for (int i = 0; i < 4; ++i) {
    const VelocityEstimate e = est->estimate(run.frame(i, img));
    EXPECT_EQ(e.method, Method::short_streak) << "frame " << i;
    EXPECT_FALSE(e.has_direction || e.has_speed) << "frame " << i;
    EXPECT_EQ(e.quality, 0.0) << "frame " << i;
  }
}


TEST(GvsEstimator, AStreakCannotShrinkFromEndlessToShortInOneFrame) {
  // 16.7 m/s under 3 ms: 500 px streaks, too long to measure. A frame that
  // then shows a measurable 44 px streak (1.5 m/s) without a recent speed
  // would mean -900 m/s^2: refused (no speed), as the texture's own grain
  // can make a "streak end" that passes every other test (docs/estimator.md,
  // "Measures against false answers"; measurements: commit 2a98d05).
  SynthRun fast;
  fast.v_mps = {16.7, 0.0};
  fast.exposure.exposure_us = 3000.0;
  auto est = make_gvs(fast.cam);
  cv::Mat img;
  for (int i = 0; i < 2; ++i) {
    const VelocityEstimate e = est->estimate(fast.frame(i, img));
    ASSERT_TRUE(e.method == Method::streak_cont || e.method == Method::streak_energy ||
                e.method == Method::streak_fwd)
        << "frame " << i << " " << e.method;
    ASSERT_FALSE(e.has_speed);
  }
  SynthRun slow = fast;
  slow.v_mps = {1.47, 0.0};
  const VelocityEstimate e = est->estimate(slow.frame(2, img));
  EXPECT_FALSE(e.has_speed) << e.method << " " << e.speed_mps;
  // The same frame with no such history is measured.
  auto fresh = make_gvs(fast.cam);
  const VelocityEstimate f = fresh->estimate(slow.frame(2, img));
  ASSERT_TRUE(f.has_speed) << f.method;
  EXPECT_NEAR(f.speed_mps, 1.47, 0.03);
}

// Ground with a grain of its own (the tiled photograph torcs_etrack2 has
// one): the texture smeared 13 px across the motion. A 15 px streak over it
// reads an elongated spectrum whose axis leans 10 deg towards the grain.
const cv::Mat& grained_texture() {
  static const cv::Mat grained = [] {
    cv::Mat line = cv::Mat::zeros(13, 13, CV_32F);
    cv::line(line, {6, 0}, {6, 12}, cv::Scalar(1.0));
    line /= cv::sum(line)[0];
    cv::Mat out;
    cv::filter2D(texture(), out, -1, line, {-1, -1}, 0.0, cv::BORDER_REFLECT);
    cv::Scalar mean;
    cv::Scalar stddev;
    cv::meanStdDev(out, mean, stddev);
    return cv::Mat((out - mean[0]) / stddev[0]);
  }();
  return grained;
}

TEST(GvsEstimator, SlowOnGrainedGroundAfterFastFramesGoesBackToThePair) {
  // After frames too fast for a pair (single-frame mode, no speed), the car
  // crawls at 0.49 m/s with 3 ms: 15 px streaks, too short for a speed, and
  // frames 83 px apart that overlap. The pair must take over again. The
  // crawl starts 83 ms after the fast frames, beyond speed_memory_s: within
  // it their speed floor (too long: at least 17.9 m/s) would say the frames
  // cannot overlap, and braking to a crawl takes a car most of a second.
  SynthRun fast;
  fast.ground = &grained_texture();
  fast.v_mps = {16.7, 0.0};
  fast.exposure.exposure_us = 600.0;  // 100 px streaks, frames 2800 px apart
  auto est = make_gvs(fast.cam);
  cv::Mat img;
  for (int i = 0; i < 2; ++i) ASSERT_NE(est->estimate(fast.frame(i, img)).method, Method::pair) << "frame " << i;
  SynthRun slow = fast;
  slow.v_mps = {0.45, 0.2};
  slow.exposure.exposure_us = 3000.0;
  int pairs = 0;
  for (int i = 6; i < 18; ++i) {
    const VelocityEstimate e = est->estimate(slow.frame(i, img));
    if (e.method != Method::pair) continue;
    ++pairs;
    EXPECT_NEAR(dir_error(e, slow.v_mps), 0.0, 0.3) << "frame " << i;
    ASSERT_TRUE(e.has_speed);
    EXPECT_NEAR(e.speed_mps, std::hypot(0.45, 0.2), 0.01) << "frame " << i;
  }
  // The first slow frame has no overlapping predecessor; the second's pair
  // has no slope for its half-frame lag (GvsEstimator keeps the frame's own).
  EXPECT_EQ(pairs, 10);
}

TEST(GvsEstimator, ShortStrobedStreaksAtSpeedTakeNoChancePair) {
  // Single-frame mode (fast frames 2800 px apart), then 12.6 m/s under a
  // 100 us strobe: 13 px streaks without a speed, as in a cold start of the
  // adaptive strobe, and frames 2098 px apart, which on this 1024 px
  // periodic ground (a tiled photograph repeats too) is a 50 px shift. The
  // pair matches it at 0.3 m/s, a speed that makes a 0.3 px streak, not the
  // 13 px one the frame shows: it must not give the speed.
  SynthRun fast;
  fast.ground = &grained_texture();
  fast.v_mps = {16.7, 0.0};
  fast.exposure.exposure_us = 600.0;
  auto est = make_gvs(fast.cam);
  cv::Mat img;
  for (int i = 0; i < 2; ++i) ASSERT_NE(est->estimate(fast.frame(i, img)).method, Method::pair) << "frame " << i;
  SynthRun run = fast;
  run.v_mps = {2098.0 * 0.1e-3 * 60.0, 0.0};
  run.exposure.exposure_us = 100.0;
  for (int i = 2; i < 12; ++i) {
    const VelocityEstimate e = est->estimate(run.frame(i, img));
    EXPECT_NE(e.method, Method::pair) << "frame " << i << " " << e.speed_mps;
    if (e.has_speed) {
      EXPECT_NEAR(e.speed_mps, run.v_mps.x, 0.3) << "frame " << i << " " << e.method;
    }
  }
}

}  // namespace
}  // namespace gvs::dsp
