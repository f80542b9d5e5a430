// The "gvs" estimator's analyses on their own (gvs_analysis.hpp), each on
// synthetic frames (gvs_synth.hpp) with a tracking state set up by hand:
// what each measures, and how the tracking state it reads steers it.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "gvs/dsp/frame_check.hpp"
#include "gvs/dsp/vocabulary.hpp"
#include "gvs/dsp/gvs_analysis.hpp"
#include "gvs_synth.hpp"

namespace gvs::dsp {
namespace {

constexpr double kFramePeriodUs = 1e6 / 60.0;
constexpr double kMPerPx = 1e-4;  // CameraGeometry's 0.1 mm/px

const cv::Mat& texture() {
  static const cv::Mat tex = test::make_texture(1024, 23);
  return tex;
}

/// A car moving at a constant vehicle velocity, filmed with `exposure`.
struct Scene {
  CameraGeometry cam;
  Vec2 v_mps{1.0, 0.0};
  ExposurePlan exposure;
  test::Sensor sensor;

  [[nodiscard]] FrameView frame(int i, cv::Mat& storage) const {
    const Vec2 px_per_us = velocity_to_image_shift(v_mps, 1e-6, cam);
    const double t0 = i * kFramePeriodUs;
    std::vector<test::Pulse> pulses;
    if (exposure.pulse_count == 0) pulses.push_back({0.0, exposure.exposure_us, 1.0});
    for (std::size_t k = 0; k < exposure.pulse_count; ++k) {
      pulses.push_back({exposure.pulses[k].start_us, exposure.pulses[k].duration_us, 1.0});
    }
    storage = test::render_frame(texture(), {cam.width_px, cam.height_px}, px_per_us.x * t0, px_per_us.y * t0,
                                 0.0, px_per_us.x, px_per_us.y, 0.0, pulses, sensor,
                                 300 + static_cast<std::uint64_t>(i));
    FrameView f;
    f.gray = storage;
    f.index = i;
    f.t_ns = std::llround(t0 * 1000.0);
    f.exposure = exposure;
    return f;
  }
};

std::int64_t t_mid(const FrameView& f) {
  return f.t_ns + std::llround(f.exposure.light_centre_us() * 1000.0);
}

double mean_grey(const FrameView& f) { return measure_frame(f.gray).mean_grey; }

double dir_error(const VelocityEstimate& e, Vec2 v) { return wrap_deg(e.direction_deg - direction_deg(v)); }

/// A tracking state whose previous frame is `f`.
TrackingState after_frame(const FrameView& f, const PairWorkspace& ws) {
  TrackingState t(f.gray.size(), ws.left.size());
  update_tracking(t, f, t_mid(f), mean_grey(f), no_estimate(f.index, t_mid(f), Method::none), FrameOutcome{});
  return t;
}

/// The motion memory of an estimate at t_ns of velocity v with a measured sign.
void remember_velocity(MotionMemory& m, Vec2 v, std::int64_t index, std::int64_t t_ns) {
  const double speed = std::hypot(v.x, v.y);
  m.has_speed = true;
  m.speed_mps = speed;
  m.speed_index = index;
  m.speed_t_ns = t_ns;
  m.has_direction = true;
  m.direction = {v.x / speed, v.y / speed};
  m.direction_t_ns = t_ns;
  m.sign_known = true;
}

TEST(GvsStillCheck, TheSameGroundIsStillAMovedOneIsNot) {
  const GvsEstimatorSettings set;
  Scene scene;
  scene.v_mps = {0.0, 0.0};
  PairWorkspace ws(cv::Size(512, 384));
  cv::Mat a;
  cv::Mat b;
  const FrameView f0 = scene.frame(0, a);
  const FrameView f1 = scene.frame(1, b);  // the same ground, new noise
  const TrackingState t = after_frame(f0, ws);
  const StillCheck still = check_still(f1.gray, mean_grey(f1), t.previous, set);
  EXPECT_TRUE(still.still);
  EXPECT_LT(still.ratio, 0.5 * set.still_ratio);

  scene.v_mps = {0.05, 0.0};  // 8 px between frames
  const FrameView moved = scene.frame(1, b);
  const StillCheck not_still = check_still(moved.gray, mean_grey(moved), t.previous, set);
  EXPECT_FALSE(not_still.still);
  EXPECT_GT(not_still.ratio, set.still_ratio);
}

// The ratio alone (StillCheck::ratio): 0 for the same ground whatever the
// light's gain, about 1 for other ground, also when both frames share the
// ring light's fall-off (the light's shape is no likeness of the ground).
TEST(Standstill, TheRatioIsWhatIsLeftOfTheFrameOnceThePreviousOneAndTheSmoothLightAreTakenOut) {
  const GvsEstimatorSettings set;
  cv::Mat ground(384, 512, CV_8UC1);
  cv::Mat other(384, 512, CV_8UC1);
  cv::theRNG().state = 7;
  cv::randu(ground, 40, 120);
  cv::randu(other, 40, 120);
  PreviousFrame previous;
  const auto ratio = [&](const cv::Mat& before, const cv::Mat& now) {
    previous.gray = before;
    previous.mean_grey = cv::mean(before)[0];
    return check_still(now, cv::mean(now)[0], previous, set).ratio;
  };
  EXPECT_EQ(ratio(ground, ground), 0.0);
  const cv::Mat brighter = 2 * ground;  // twice the light, nothing clipped
  EXPECT_NEAR(ratio(ground, brighter), 0.0, 1e-12);
  // Other ground of the same contrast: the two frames' variances add, over twice one.
  EXPECT_NEAR(ratio(ground, other), 1.0, 0.03);
  // Faint ground (20 grey levels) under a fall-off of 60 grey levels from
  // the centre, the same in both frames: most of each frame's variance.
  const auto lit = [](const cv::Mat& texture) {
    cv::Mat out(texture.size(), CV_8UC1);
    for (int r = 0; r < out.rows; ++r) {
      for (int c = 0; c < out.cols; ++c) {
        const double r2 = (std::pow(r - 192.0, 2) + std::pow(c - 256.0, 2)) / (320.0 * 320.0);
        out.at<std::uint8_t>(r, c) = cv::saturate_cast<std::uint8_t>(texture.at<std::uint8_t>(r, c) / 4 + 60.0 * (1.0 - r2));
      }
    }
    return out;
  };
  EXPECT_GT(ratio(lit(ground), lit(other)), 0.8);
  EXPECT_LT(ratio(lit(ground), lit(ground)), 1e-12);
}

TEST(GvsPairAnalysis, TheShiftBetweenFramesGivesTheSignedVelocity) {
  const GvsEstimatorSettings set;
  Scene scene;
  scene.v_mps = {-0.7, 0.15};  // reversing: 118 px between frames
  PairWorkspace ws(cv::Size(512, 384));
  cv::Mat a;
  cv::Mat b;
  const FrameView f0 = scene.frame(0, a);
  const FrameView f1 = scene.frame(1, b);
  const TrackingState t = after_frame(f0, ws);
  const double dt_s = static_cast<double>(t_mid(f1) - t_mid(f0)) * 1e-9;
  const PairResult r = analyse_pair(f1, t_mid(f1), dt_s, mean_grey(f1), t, scene.cam, set, ws);
  ASSERT_TRUE(r.matched);
  EXPECT_EQ(r.estimate.method, Method::pair);
  EXPECT_NEAR(r.v_pair_mps.x, -0.7, 0.01);
  EXPECT_NEAR(r.v_pair_mps.y, 0.15, 0.01);
  // No earlier pair or estimate: no lag compensation.
  EXPECT_EQ(r.estimate.vx_mps, r.v_pair_mps.x);
  EXPECT_TRUE(r.estimate.has_yaw_rate);
  EXPECT_NEAR(r.estimate.yaw_rate_dps, 0.0, 3.0);
  EXPECT_GT(r.estimate.quality, 0.5);
}

TEST(GvsPairAnalysis, TheTrackedMotionCompensatesTheLagAndRejectsATurnAround) {
  const GvsEstimatorSettings set;
  Scene scene;
  scene.v_mps = {0.9, 0.0};
  PairWorkspace ws(cv::Size(512, 384));
  cv::Mat a;
  cv::Mat b;
  const FrameView f0 = scene.frame(0, a);
  const FrameView f1 = scene.frame(1, b);
  TrackingState t = after_frame(f0, ws);
  const double dt_s = static_cast<double>(t_mid(f1) - t_mid(f0)) * 1e-9;

  // The previous pair was 0.1 m/s slower: v = v_pair + (v_pair - v_prev) / 2.
  note_pair(t.motion, true, {0.8, 0.0});
  PairResult r = analyse_pair(f1, t_mid(f1), dt_s, mean_grey(f1), t, scene.cam, set, ws);
  ASSERT_TRUE(r.matched);
  EXPECT_NEAR(r.estimate.vx_mps - r.v_pair_mps.x, 0.5 * (r.v_pair_mps.x - 0.8), 1e-9);
  // ... clamped to max_accel_mps2: a previous pair 1 m/s slower is not physical.
  note_pair(t.motion, true, {-0.1, 0.0});
  r = analyse_pair(f1, t_mid(f1), dt_s, mean_grey(f1), t, scene.cam, set, ws);
  EXPECT_NEAR(r.estimate.vx_mps - r.v_pair_mps.x, set.max_accel_mps2 * dt_s / 2.0, 1e-9);

  // A measured direction the other way, 17 ms ago: the pair cannot have turned round.
  note_pair(t.motion, false, {});
  remember_velocity(t.motion, {-0.9, 0.0}, 0, t_mid(f0));
  r = analyse_pair(f1, t_mid(f1), dt_s, mean_grey(f1), t, scene.cam, set, ws);
  EXPECT_FALSE(r.matched);
  EXPECT_EQ(r.estimate.quality, 0.0);
  // ... unless that direction's sign was only assumed.
  t.motion.sign_known = false;
  r = analyse_pair(f1, t_mid(f1), dt_s, mean_grey(f1), t, scene.cam, set, ws);
  EXPECT_TRUE(r.matched);
}

/// A frame blurred by a streak of v x exposure (no pair: one frame only).
struct Blurred {
  Scene scene;
  cv::Mat storage;
  FrameView frame;
  Blurred(Vec2 v_mps, double exposure_us) {
    scene.v_mps = v_mps;
    scene.exposure.exposure_us = exposure_us;
    frame = scene.frame(5, storage);
  }
};

StreakResult streak_of(const FrameView& f, const TrackingState& t, SpectrumWorkspace& ws) {
  return analyse_streak(f, t_mid(f), mean_grey(f), t, CameraGeometry{}, GvsEstimatorSettings{}, ws);
}

TEST(GvsStreakAnalysis, TheStreakGivesAxisAndSpeedAndTheTrackedDirectionTheSign) {
  const Blurred b({-6.0, 0.8}, 1000.0);  // reversing; a 61 px streak
  SpectrumWorkspace ws(b.frame.gray.size());
  TrackingState t(b.frame.gray.size(), cv::Size(320, 384));
  // No history: speed and axis, the sign assumed forwards.
  StreakResult r = streak_of(b.frame, t, ws);
  EXPECT_EQ(r.estimate.method, Method::blur_fwd);
  ASSERT_TRUE(r.estimate.has_speed && r.estimate.has_direction);
  EXPECT_NEAR(r.estimate.speed_mps, std::hypot(6.0, 0.8), 0.02 * 6.0);
  EXPECT_NEAR(dir_error(r.estimate, {6.0, -0.8}), 0.0, 0.5);
  EXPECT_FALSE(r.sign_known);
  EXPECT_TRUE(r.note.axis_measured);
  EXPECT_FALSE(r.note.too_long);

  // A measured backward direction 17 ms ago: continuity keeps it.
  remember_velocity(t.motion, b.scene.v_mps, b.frame.index - 1, t_mid(b.frame) - 16666667);
  r = streak_of(b.frame, t, ws);
  EXPECT_EQ(r.estimate.method, Method::blur_cont);
  EXPECT_NEAR(dir_error(r.estimate, b.scene.v_mps), 0.0, 0.5);
  EXPECT_NEAR(r.estimate.speed_mps, std::hypot(6.0, 0.8), 0.02 * 6.0);
  EXPECT_TRUE(r.sign_known);

  // A recent speed twice the true one: the streak end is searched only
  // near it, so the true end is not taken (no speed, direction only).
  t.motion.speed_mps = 2.0 * std::hypot(6.0, 0.8);
  r = streak_of(b.frame, t, ws);
  EXPECT_TRUE(r.estimate.has_direction);
  EXPECT_FALSE(r.estimate.has_speed);
}

TEST(GvsStreakAnalysis, AStreakLongerThanTheFrameGivesADirectionAndASpeedFloor) {
  const Blurred b({25.0, 0.0}, 1000.0);  // 250 px
  SpectrumWorkspace ws(b.frame.gray.size());
  const TrackingState t(b.frame.gray.size(), cv::Size(320, 384));
  const StreakResult r = streak_of(b.frame, t, ws);
  EXPECT_EQ(r.estimate.method, Method::streak_fwd);
  EXPECT_FALSE(r.estimate.has_speed);
  EXPECT_NEAR(dir_error(r.estimate, b.scene.v_mps), 0.0, 0.5);
  ASSERT_TRUE(r.note.too_long);
  // Half the longest measurable streak along the rows (the axis, within a
  // few hundredths of a degree), over the light time.
  const double longest_px = GvsEstimatorSettings{}.max_streak_fraction * b.frame.gray.rows;
  const double floor_mps = 0.5 * longest_px * kMPerPx / 1e-3;
  EXPECT_NEAR(r.note.speed_floor_mps, floor_mps, 0.005 * floor_mps);
  EXPECT_LT(r.note.speed_floor_mps, 25.0);
}

TEST(GvsStreakAnalysis, AStreakOfAFewPixelsGivesNoDirection) {
  const Blurred b({25.0, 3.0}, 12.0);  // 3 px
  SpectrumWorkspace ws(b.frame.gray.size());
  const TrackingState t(b.frame.gray.size(), cv::Size(320, 384));
  const StreakResult r = streak_of(b.frame, t, ws);
  EXPECT_EQ(r.estimate.method, Method::short_streak);
  EXPECT_EQ(r.estimate.quality, 0.0);
  EXPECT_FALSE(r.estimate.has_direction);
  EXPECT_TRUE(r.note.axis_measured);
  EXPECT_LT(r.note.anisotropy, GvsEstimatorSettings{}.min_anisotropy);
}

/// A frame lit by two pulses `gap_us` apart, of 4 and `second_us` us.
struct DoubleLit {
  Scene scene;
  cv::Mat storage;
  FrameView frame;
  DoubleLit(Vec2 v_mps, double second_us) {
    scene.v_mps = v_mps;
    scene.exposure.pulse_count = 2;
    scene.exposure.pulses[0] = {0.0, 4.0};
    scene.exposure.pulses[1] = {300.0, second_us};
    scene.exposure.exposure_us = 300.0 + second_us;
    frame = scene.frame(3, storage);
  }
};

DoublePulseResult double_of(const FrameView& f, const TrackingState& t, SpectrumWorkspace& ws) {
  return analyse_double_pulse(f, t_mid(f), t, CameraGeometry{}, GvsEstimatorSettings{}, ws);
}

TEST(GvsDoublePulseAnalysis, TheDisplacementOverThePulseGapGivesTheVelocity) {
  const DoubleLit d({30.0, 2.0}, 4.0);  // 108 km/h: 90 px between the images
  SpectrumWorkspace ws(d.frame.gray.size());
  TrackingState t(d.frame.gray.size(), cv::Size(320, 384));
  DoublePulseResult r = double_of(d.frame, t, ws);
  EXPECT_EQ(r.estimate.method, Method::dpiv_fwd);
  ASSERT_TRUE(r.estimate.has_speed);
  EXPECT_NEAR(r.estimate.speed_mps, std::hypot(30.0, 2.0), 0.005 * 30.0);
  EXPECT_NEAR(dir_error(r.estimate, d.scene.v_mps), 0.0, 0.1);
  EXPECT_FALSE(r.sign_known);
  // A recent speed of half the true one: the displacement is not searched that far.
  remember_velocity(t.motion, {15.0, 1.0}, d.frame.index - 1, t_mid(d.frame) - 16666667);
  r = double_of(d.frame, t, ws);
  EXPECT_EQ(r.estimate.method, Method::no_match);
  EXPECT_EQ(r.estimate.quality, 0.0);
}

TEST(GvsDoublePulseAnalysis, UnequalPulsesGiveTheSignWithoutHistory) {
  const DoubleLit d({-25.0, 3.0}, 2.0);  // backwards; the second pulse half the energy
  SpectrumWorkspace ws(d.frame.gray.size());
  const TrackingState t(d.frame.gray.size(), cv::Size(320, 384));
  const DoublePulseResult r = double_of(d.frame, t, ws);
  EXPECT_EQ(r.estimate.method, Method::dpiv_energy);
  EXPECT_TRUE(r.sign_known);
  EXPECT_NEAR(dir_error(r.estimate, d.scene.v_mps), 0.0, 0.2);
}

}  // namespace
}  // namespace gvs::dsp
