// The "gvs" estimator's tracking state on its own (gvs_tracking.hpp): the
// rules that carry mode, sign, speed and the previous frame from one frame
// to the next, and the sensor pattern learnt over frames.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>

#include <opencv2/core.hpp>

#include "gvs/dsp/gvs_tracking.hpp"
#include "streak_end.hpp"

namespace gvs::dsp {
namespace {

constexpr std::int64_t kMs = 1000000;  // ns

/// A memory holding a last estimate of `speed_mps` (quality > 0).
MotionMemory with_last_speed(double speed_mps, MotionMemory::Mode mode) {
  MotionMemory m;
  m.mode = mode;
  m.last_valid = true;
  m.last.has_speed = true;
  m.last.speed_mps = speed_mps;
  return m;
}

TEST(GvsTracking, ModeSwitchesOnTheExpectedShiftWithHysteresis) {
  const GvsEstimatorSettings set;
  const CameraGeometry cam;  // 0.1 mm/px
  const double dt_s = 1.0 / 60.0;
  // Speed that moves the ground by `px` between frames.
  const auto speed_for = [&](double px) { return px * cam.mm_per_px * 1e-3 / dt_s; };
  using Mode = MotionMemory::Mode;
  const double between = 0.5 * (set.pair_enter_shift_px + set.pair_leave_shift_px);
  EXPECT_EQ(next_mode(with_last_speed(speed_for(between), Mode::pair), dt_s, cam, set), Mode::pair);
  EXPECT_EQ(next_mode(with_last_speed(speed_for(between), Mode::single), dt_s, cam, set), Mode::single);
  EXPECT_EQ(next_mode(with_last_speed(speed_for(set.pair_leave_shift_px + 1.0), Mode::pair), dt_s, cam, set),
            Mode::single);
  EXPECT_EQ(next_mode(with_last_speed(speed_for(set.pair_enter_shift_px - 1.0), Mode::single), dt_s, cam, set),
            Mode::pair);
  // Without a last speed (or a last estimate) the mode stays.
  MotionMemory no_speed = with_last_speed(100.0, Mode::single);
  no_speed.last.has_speed = false;
  EXPECT_EQ(next_mode(no_speed, dt_s, cam, set), Mode::single);
  MotionMemory invalid = with_last_speed(100.0, Mode::pair);
  invalid.last_valid = false;
  EXPECT_EQ(next_mode(invalid, dt_s, cam, set), Mode::pair);
}

TEST(GvsTracking, SignFollowsTheLastDirectionThenEnergyThenForward) {
  const GvsEstimatorSettings set;
  MotionMemory m;
  m.has_direction = true;
  m.direction = {-1.0, 0.0};  // reversing
  m.direction_t_ns = 1000 * kMs;
  m.sign_known = true;
  const std::int64_t now = m.direction_t_ns + 17 * kMs;

  // An axis 20 deg off the last direction, either way round: continuity.
  const Vec2 axis{std::cos(deg_to_rad(20.0)), std::sin(deg_to_rad(20.0))};
  SignChoice c = choose_sign(m, axis, now, 0.0, set);
  EXPECT_EQ(c.source, SignSource::continuity);
  EXPECT_EQ(c.sign, -1.0);
  EXPECT_TRUE(c.known);
  m.sign_known = false;  // continuity carries an assumed sign as assumed
  EXPECT_FALSE(choose_sign(m, axis, now, 0.0, set).known);

  // Turned by 80 deg (not physical between frames), or a direction older
  // than continuity_max_age_s: the energy vote, else forwards.
  const Vec2 across{std::cos(deg_to_rad(80.0)), std::sin(deg_to_rad(80.0))};
  c = choose_sign(m, across, now, -2.0 * set.min_energy_confidence, set);
  EXPECT_EQ(c.source, SignSource::energy);
  EXPECT_EQ(c.sign, -1.0);
  EXPECT_TRUE(c.known);
  const std::int64_t late = m.direction_t_ns + static_cast<std::int64_t>((set.continuity_max_age_s + 0.01) * 1e9);
  c = choose_sign(m, axis, late, 0.5 * set.min_energy_confidence, set);
  EXPECT_EQ(c.source, SignSource::forward);
  EXPECT_EQ(c.sign, 1.0);  // axis.x > 0
  EXPECT_FALSE(c.known);
  EXPECT_EQ(choose_sign(m, {-axis.x, -axis.y}, late, 0.0, set).sign, -1.0);  // -axis flipped: forwards

  EXPECT_GT(sign_quality(SignSource::continuity), sign_quality(SignSource::energy));
  EXPECT_GT(sign_quality(SignSource::energy), sign_quality(SignSource::forward));
}

TEST(GvsTracking, ASpeedIsRecentForSpeedMemoryOnly) {
  const GvsEstimatorSettings set;
  MotionMemory m;
  m.speed_t_ns = 5000 * kMs;
  const auto memory_ns = static_cast<std::int64_t>(set.speed_memory_s * 1e9);
  EXPECT_FALSE(speed_is_recent(m, m.speed_t_ns + kMs, set));  // no speed yet
  m.has_speed = true;
  EXPECT_TRUE(speed_is_recent(m, m.speed_t_ns + kMs, set));
  EXPECT_TRUE(speed_is_recent(m, m.speed_t_ns + memory_ns, set));
  EXPECT_FALSE(speed_is_recent(m, m.speed_t_ns + memory_ns + kMs, set));
  EXPECT_FALSE(speed_is_recent(m, m.speed_t_ns, set));  // the same frame is not "before"
}

TEST(GvsTracking, TheStreakSearchLooksAroundARecentSpeedAndTheCepstrumBeyondTheWindow) {
  // 3 ms at 0.1 mm/px: 1 m/s draws a 30 px streak. A 384 px extent: the
  // window measures up to 161 px (max_streak_fraction), the cepstrum looks
  // up to 192 px (cepstrum_max_streak_fraction).
  const GvsEstimatorSettings set;
  constexpr double kExtentPx = 384.0;
  constexpr double kLightS = 3e-3;
  constexpr double kMetresPerPx = 1e-4;
  constexpr std::int64_t kFrameNs = 16667 * 1000;
  MotionMemory m;
  m.speed_index = 100;
  m.speed_t_ns = 100 * kFrameNs;

  // No speed: everywhere, with the cold gates; the cepstrum over every
  // length a streak can show without an alias nearer.
  const StreakSearch cold = streak_search(m, 101, 101 * kFrameNs, kExtentPx, kLightS, kMetresPerPx, set);
  EXPECT_DOUBLE_EQ(cold.hi_px, set.max_streak_fraction * kExtentPx);
  EXPECT_DOUBLE_EQ(cold.cepstrum_hi_px, set.cepstrum_max_streak_fraction * kExtentPx);
  EXPECT_TRUE(cold.cepstrum_sees_all);
  EXPECT_DOUBLE_EQ(cold.min_significance, set.min_streak_significance_cold);

  // 3 m/s a frame ago: 90 px, the window +-15 % plus 20 m/s^2 for 16.7 ms
  // (and 2 px): 64.5-115.5 px, all inside the window; the cepstrum looks
  // at the same lengths.
  m.has_speed = true;
  m.speed_mps = 3.0;
  const StreakSearch near = streak_search(m, 101, 101 * kFrameNs, kExtentPx, kLightS, kMetresPerPx, set);
  EXPECT_NEAR(near.lo_px, 64.5, 0.1);
  EXPECT_NEAR(near.hi_px, 115.5, 0.1);
  EXPECT_DOUBLE_EQ(near.cepstrum_hi_px, near.hi_px);
  EXPECT_TRUE(near.cepstrum_sees_all);
  EXPECT_DOUBLE_EQ(near.min_significance, set.min_streak_significance);

  // 4.5 m/s: up to 167.3 px, beyond the window but not the cepstrum's reach.
  m.speed_mps = 4.5;
  const StreakSearch wide = streak_search(m, 101, 101 * kFrameNs, kExtentPx, kLightS, kMetresPerPx, set);
  EXPECT_DOUBLE_EQ(wide.hi_px, set.max_streak_fraction * kExtentPx);
  EXPECT_NEAR(wide.cepstrum_hi_px, 167.3, 0.1);
  EXPECT_TRUE(wide.cepstrum_sees_all);

  // 5.5 m/s: up to 201.7 px, beyond both: the cepstrum cannot vouch.
  m.speed_mps = 5.5;
  const StreakSearch beyond = streak_search(m, 101, 101 * kFrameNs, kExtentPx, kLightS, kMetresPerPx, set);
  EXPECT_DOUBLE_EQ(beyond.cepstrum_hi_px, set.cepstrum_max_streak_fraction * kExtentPx);
  EXPECT_FALSE(beyond.cepstrum_sees_all);

  // Older than speed_memory_s: cold gates, everywhere. 5.5 m/s five frames
  // ago allows up to 239.8 px now, beyond the cepstrum's reach: no
  // re-acquisition.
  const StreakSearch stale = streak_search(m, 105, 105 * kFrameNs, kExtentPx, kLightS, kMetresPerPx, set);
  EXPECT_DOUBLE_EQ(stale.min_significance, set.min_streak_significance_cold);
  EXPECT_DOUBLE_EQ(stale.hi_px, set.max_streak_fraction * kExtentPx);
  EXPECT_TRUE(stale.cepstrum_sees_all);
  EXPECT_FALSE(stale.reacquire);
  // 3 m/s five frames ago: 24.5-155.5 px, within reach: re-acquisition.
  m.speed_mps = 3.0;
  const StreakSearch again = streak_search(m, 105, 105 * kFrameNs, kExtentPx, kLightS, kMetresPerPx, set);
  EXPECT_DOUBLE_EQ(again.min_significance, set.min_streak_significance_cold);
  EXPECT_TRUE(again.reacquire);
  EXPECT_NEAR(again.reacquire_lo_px, 24.5, 0.1);
  EXPECT_NEAR(again.reacquire_hi_px, 155.5, 0.1);
  // ... but not from a speed older than reacquire_memory_s (a 0.3 ms
  // strobe, whose streaks stay within reach that long).
  constexpr double kStrobeS = 0.3e-3;
  const auto last_index = static_cast<std::int64_t>(std::floor(set.reacquire_memory_s * 60.0)) + 99;
  EXPECT_TRUE(streak_search(m, last_index, last_index * kFrameNs, kExtentPx, kStrobeS, kMetresPerPx, set).reacquire);
  EXPECT_FALSE(
      streak_search(m, last_index + 2, (last_index + 2) * kFrameNs, kExtentPx, kStrobeS, kMetresPerPx, set).reacquire);
}

TEST(GvsTracking, AVelocityFollowsThePreviousFramesWithinWhatTheCarCanChange) {
  // 1.5 m/s backwards (5.4 km/h) at frame 255; 1/60 s later the car can be
  // within 0.15 x 1.5 + 20 x 1/60 = 0.56 m/s of it.
  const GvsEstimatorSettings set;
  constexpr double kDtS = 1.0 / 60.0;
  MotionMemory m = with_last_speed(1.5, MotionMemory::Mode::single);
  m.last.index = 255;
  m.last.has_direction = true;
  m.last.vx_mps = -1.5;
  VelocityEstimate e;
  e.has_speed = true;
  e.has_direction = true;
  const auto at = [&](double vx_mps, double vy_mps) {
    e.vx_mps = vx_mps;
    e.vy_mps = vy_mps;
    e.speed_mps = std::hypot(vx_mps, vy_mps);
    return follows_last_velocity(m, e, 256, kDtS, set);
  };
  EXPECT_TRUE(at(-1.5, 0.0));
  EXPECT_TRUE(at(-1.0, 0.0));
  EXPECT_FALSE(at(-0.9, 0.0));
  EXPECT_TRUE(at(-1.5, 0.5));
  // The circular alias of a 250 px shift along 384 px: 134 px the other way.
  EXPECT_FALSE(at(0.8, 0.0));
  // Nothing to compare with: an older last estimate, or none with a direction.
  EXPECT_TRUE(follows_last_velocity(m, e, 257, kDtS, set));
  m.last.has_direction = false;
  EXPECT_TRUE(at(0.8, 0.0));
}

TEST(GvsTracking, ATooLongStreakKeepsThePairOffWhileTheCarCannotHaveSlowedIntoIt) {
  const GvsEstimatorSettings set;
  const CameraGeometry cam;  // 0.1 mm/px
  const double dt_s = 1.0 / 60.0;
  // The pair's longest shift, 200 px of 0.1 mm in 16.7 ms: 1.2 m/s.
  const double pair_max_mps = set.pair_max_shift_px * cam.mm_per_px * 1e-3 / dt_s;
  ASSERT_NEAR(pair_max_mps, 1.2, 1e-9);
  MotionMemory m;
  const std::int64_t t0 = 1000 * kMs;
  EXPECT_EQ(speed_floor_now_mps(m, t0, set), 0.0);  // no floor: nothing known
  EXPECT_TRUE(pair_can_overlap(m, t0, dt_s, cam, set));

  // A 3 ms frame whose streak outgrew the frame: at least 2.7 m/s (half of 161 px in 3 ms).
  SingleFrameNote too_long;
  too_long.too_long = true;
  too_long.speed_floor_mps = 2.7;
  note_single(m, too_long, t0);
  const auto frame_ns = static_cast<std::int64_t>(dt_s * 1e9);
  // One frame on, braking at max_accel_mps2 (20 m/s^2) takes off 0.33 m/s.
  EXPECT_NEAR(speed_floor_now_mps(m, t0 + frame_ns, set), 2.7 - set.max_accel_mps2 * dt_s, 1e-6);
  EXPECT_FALSE(pair_can_overlap(m, t0 + frame_ns, dt_s, cam, set));
  // Older than speed_memory_s the floor says nothing.
  const auto memory_ns = static_cast<std::int64_t>(set.speed_memory_s * 1e9);
  EXPECT_EQ(speed_floor_now_mps(m, t0 + memory_ns + kMs, set), 0.0);
  EXPECT_TRUE(pair_can_overlap(m, t0 + memory_ns + kMs, dt_s, cam, set));

  // A floor the car can have braked below the pair's reach since: the pair is tried.
  too_long.speed_floor_mps = 1.4;  // 1.4 - 0.33 = 1.07 m/s <= 1.2
  note_single(m, too_long, t0);
  EXPECT_TRUE(pair_can_overlap(m, t0 + frame_ns, dt_s, cam, set));
  // Frames further apart reach further: 1.07 m/s against 0.6 m/s at 30 fps.
  EXPECT_FALSE(pair_can_overlap(m, t0 + frame_ns, 2.0 * dt_s, cam, set));
}

TEST(GvsTracking, PairAndSingleFrameNotes) {
  MotionMemory m;
  note_pair(m, true, {1.5, -0.2});
  EXPECT_TRUE(m.has_pair_v);
  EXPECT_EQ(m.pair_v_mps.x, 1.5);
  note_pair(m, false, {9.0, 9.0});
  EXPECT_FALSE(m.has_pair_v);

  SingleFrameNote note;
  note.axis_measured = true;
  note.anisotropy = 0.72;
  note.dark = true;
  note_single(m, note, 100 * kMs);
  EXPECT_EQ(m.last_axis_anisotropy, 0.72);
  EXPECT_TRUE(m.last_single_dark);
  EXPECT_FALSE(m.has_speed_floor);
  // A frame that measured no axis keeps the last anisotropy; too long sets the floor.
  SingleFrameNote too_long;
  too_long.too_long = true;
  too_long.speed_floor_mps = 2.7;
  note_single(m, too_long, 117 * kMs);
  EXPECT_EQ(m.last_axis_anisotropy, 0.72);
  EXPECT_FALSE(m.last_single_dark);
  EXPECT_TRUE(m.has_speed_floor);
  EXPECT_EQ(m.speed_floor_mps, 2.7);
  EXPECT_EQ(m.speed_floor_t_ns, 117 * kMs);
}

TEST(GvsTracking, UpdateKeepsTheFrameAndWhatTheEstimateMeasured) {
  const cv::Size size(128, 96);
  const cv::Size half(80, 96);
  TrackingState t(size, half);
  const std::uint8_t* kept_pixels = t.previous.gray.data;

  cv::Mat gray(size, CV_8UC1);
  cv::randu(gray, 0, 255);
  FrameView f;
  f.gray = gray;
  f.index = 7;
  f.exposure.exposure_us = 2000.0;
  HalfSpectra halves;
  halves.left.create(half, CV_32FC2);
  halves.right.create(half, CV_32FC2);
  halves.pattern_out = true;
  const void* halves_left = halves.left.data;

  VelocityEstimate e = no_estimate(7, 50 * kMs, Method::blur_fwd);
  e.quality = 0.4;
  e.has_direction = true;
  e.direction_deg = 90.0;  // no speed: direction only
  FrameOutcome outcome;
  outcome.sign_known = true;
  outcome.halves = &halves;
  update_tracking(t, f, 50 * kMs, 80.0, e, outcome);

  EXPECT_TRUE(t.previous.valid);
  EXPECT_EQ(t.previous.gray.data, kept_pixels);  // copied into the buffer made once
  EXPECT_EQ(cv::norm(t.previous.gray, gray, cv::NORM_INF), 0.0);
  EXPECT_EQ(t.previous.lit_us, 2000.0);
  EXPECT_EQ(t.previous.mean_grey, 80.0);
  EXPECT_EQ(t.previous.t_mid_ns, 50 * kMs);
  EXPECT_TRUE(t.previous.has_halves);
  EXPECT_EQ(t.previous.halves.left.data, halves_left);  // swapped in, not copied
  EXPECT_TRUE(t.previous.halves.pattern_out);
  EXPECT_TRUE(t.motion.last_valid);
  EXPECT_FALSE(t.motion.has_speed);
  ASSERT_TRUE(t.motion.has_direction);
  EXPECT_NEAR(t.motion.direction.y, 1.0, 1e-12);
  EXPECT_TRUE(t.motion.sign_known);

  // An estimate of quality 0 neither teaches a speed nor a direction.
  VelocityEstimate none = no_estimate(8, 67 * kMs, Method::no_match);
  none.has_speed = true;
  none.speed_mps = 3.0;
  f.index = 8;
  update_tracking(t, f, 67 * kMs, 80.0, none, FrameOutcome{});
  EXPECT_FALSE(t.motion.last_valid);
  EXPECT_FALSE(t.motion.has_speed);
  EXPECT_EQ(t.motion.direction_t_ns, 50 * kMs);
  EXPECT_FALSE(t.previous.has_halves);

  VelocityEstimate fast = no_estimate(9, 84 * kMs, Method::blur_cont);
  fast.quality = 0.9;
  fast.has_speed = true;
  fast.speed_mps = 12.0;
  update_tracking(t, f, 84 * kMs, 80.0, fast, FrameOutcome{});
  EXPECT_TRUE(t.motion.has_speed);
  EXPECT_EQ(t.motion.speed_mps, 12.0);
  EXPECT_EQ(t.motion.speed_index, 9);
  EXPECT_EQ(t.motion.speed_t_ns, 84 * kMs);
}

TEST(GvsTracking, AnUnusableFrameBreaksThePairsAndResetForgetsAll) {
  TrackingState t(cv::Size(64, 64), cv::Size(40, 64));
  t.previous.valid = true;
  t.previous.has_halves = true;
  t.motion.has_pair_v = true;
  t.motion.last_valid = true;
  t.motion.has_speed = true;
  t.motion.has_direction = true;
  note_unusable_frame(t, no_estimate(3, 0, Method::dark));
  EXPECT_FALSE(t.previous.valid || t.previous.has_halves || t.motion.has_pair_v || t.motion.last_valid);
  EXPECT_EQ(t.motion.last.method, Method::dark);
  EXPECT_TRUE(t.motion.has_speed && t.motion.has_direction);  // still known, by their time

  cv::Mat frame(64, 64, CV_8UC1, cv::Scalar(50));
  for (int i = 0; i < 20; ++i) t.pattern.learn_columns(frame, 40.0);
  t.pattern.learn_pixels(frame, 40.0);
  t.motion.mode = MotionMemory::Mode::single;
  t.motion.last_axis_anisotropy = 0.5;
  forget_tracking(t);
  EXPECT_FALSE(t.motion.has_speed || t.motion.has_direction || t.motion.has_speed_floor);
  EXPECT_EQ(t.motion.mode, MotionMemory::Mode::pair);
  EXPECT_EQ(t.pattern.columns(), nullptr);
  EXPECT_EQ(t.pattern.pixel_frames(), 0);
  EXPECT_EQ(cv::norm(t.pattern.pixels(), cv::NORM_INF), 0.0);
  EXPECT_EQ(t.motion.last_axis_anisotropy, 0.5);
}

TEST(SensorPattern, LearnsTheColumnAndPixelOffsetsFromMovingGround) {
  const cv::Size size(160, 120);
  SensorPattern p(size);
  // The sensor's offsets: per column (+-3 grey levels) and per pixel (+-2).
  cv::Mat column_offsets(1, size.width, CV_32F);
  cv::Mat pixel_offsets(size, CV_32F);
  cv::RNG rng(5);
  rng.fill(column_offsets, cv::RNG::UNIFORM, -3.0, 3.0);
  rng.fill(pixel_offsets, cv::RNG::UNIFORM, -2.0, 2.0);
  const cv::Mat sensor = cv::repeat(column_offsets, size.height, 1) + pixel_offsets;
  for (int i = 0; i < 100; ++i) {
    if (i == SensorPattern::kColumnMinFrames - 1) {
      EXPECT_EQ(p.columns(), nullptr);
    }
    // New ground every frame: texture of 4 grey levels RMS around 100.
    cv::Mat ground(size, CV_32F);
    rng.fill(ground, cv::RNG::NORMAL, 100.0, 4.0);
    cv::Mat gray;
    cv::Mat(ground + sensor).convertTo(gray, CV_8U);
    const double mean_grey = cv::mean(gray)[0];
    p.learn_columns(gray, mean_grey);
    p.learn_pixels(gray, mean_grey);
  }
  ASSERT_NE(p.columns(), nullptr);
  EXPECT_EQ(p.pixel_frames(), 100);
  const cv::Scalar column_mean = cv::mean(column_offsets);
  double column_err_sq = 0.0;
  for (int c = 0; c < size.width; ++c) {
    const double truth = static_cast<double>(column_offsets.at<float>(0, c)) - column_mean[0] + cv::mean(pixel_offsets.col(c))[0] -
                         cv::mean(pixel_offsets)[0];
    column_err_sq += std::pow(static_cast<double>(p.columns()[c]) - truth, 2);
  }
  // Texture of 4 grey levels averaged over 120 rows x 50-100 frames: ~0.05 left.
  EXPECT_LT(std::sqrt(column_err_sq / size.width), 0.2);
  cv::Mat expected = sensor - cv::mean(sensor)[0];
  // Per pixel, 4 grey levels averaged over 100 frames: ~0.4 left, against ~2.1 RMS of offsets.
  const double err_rms = cv::norm(p.pixels(), expected, cv::NORM_L2) / std::sqrt(size.area());
  const double offsets_rms = cv::norm(expected, cv::NORM_L2) / std::sqrt(size.area());
  EXPECT_LT(err_rms, 0.5 * offsets_rms);
}

TEST(SensorPattern, FineTextureEnergyIsTheMeanSquareStepOverFourPixels) {
  // Stripes 4 columns wide, 100 and 110: every step over 4 px along a row
  // is +-10, down a column 0, so the mean square step is (100 + 0) / 2.
  cv::Mat stripes(40, 64, CV_8UC1);
  for (int c = 0; c < stripes.cols; ++c) stripes.col(c).setTo((c / 4) % 2 == 0 ? 100 : 110);
  EXPECT_DOUBLE_EQ(SensorPattern::fine_texture_energy(stripes), 50.0);
  // A smooth ramp counts as its step only: 40 grey levels across 64 columns
  // (far steeper than a ring light's fall-off across 512) step 2.5 over
  // 4 px, about 3 in all.
  cv::Mat ramp(40, 64, CV_8UC1);
  for (int c = 0; c < ramp.cols; ++c) ramp.col(c).setTo(100 + (40 * c) / 63);
  EXPECT_LT(SensorPattern::fine_texture_energy(ramp), 4.0);
}

TEST(GvsTracking, AReversalComesThroughASlowFrameOrIsSeenTwice) {
  // Forwards (0 deg, sign measured) until frame 171; frames 172-174 gave
  // nothing. At frame 175 a pair reads 0.24 m/s backwards: a tiled ground
  // matching its repeat, or a car that braked to a stop and reversed.
  const GvsEstimatorSettings set;
  constexpr double kDtS = 1.0 / 60.0;
  constexpr std::int64_t kT175Ns = 2'918'166'667;
  MotionMemory m;
  m.has_direction = true;
  m.sign_known = true;
  m.direction = {1.0, 0.0};
  m.direction_t_ns = kT175Ns - 66'666'667;  // frame 171
  m.last.index = 174;                        // no speed
  const Vec2 back{-0.24, 0.0};
  EXPECT_EQ(judge_reversal(m, back, 175, kT175Ns, kDtS, set), Reversal::held);
  // Sideways is no reversal; neither is anything once the direction is
  // older than continuity_max_age_s, or its sign was only assumed.
  EXPECT_EQ(judge_reversal(m, {0.01, 0.3}, 175, kT175Ns, kDtS, set), Reversal::none);
  EXPECT_EQ(judge_reversal(m, back, 175, m.direction_t_ns + 510'000'000, kDtS, set), Reversal::none);
  m.sign_known = false;
  EXPECT_EQ(judge_reversal(m, back, 175, kT175Ns, kDtS, set), Reversal::none);
  m.sign_known = true;

  // The previous frame measured 0.08 m/s forwards: the car can be at
  // -0.24 m/s 1/60 s later (0.32 <= 0.15 x 0.08 + 20 / 60).
  m.last_valid = true;
  m.last.has_speed = true;
  m.last.has_direction = true;
  m.last.vx_mps = 0.08;
  m.last.speed_mps = 0.08;
  EXPECT_EQ(judge_reversal(m, back, 175, kT175Ns, kDtS, set), Reversal::from_slow);
  // ... or stood still (a speed without a direction).
  m.last.has_direction = false;
  m.last.vx_mps = 0.0;
  m.last.speed_mps = 0.0;
  EXPECT_EQ(judge_reversal(m, back, 175, kT175Ns, kDtS, set), Reversal::from_slow);
  // At 1.1 m/s forwards it cannot.
  m.last.has_direction = true;
  m.last.vx_mps = 1.1;
  m.last.speed_mps = 1.1;
  EXPECT_EQ(judge_reversal(m, back, 175, kT175Ns, kDtS, set), Reversal::held);

  // Held at 175, the next frame's pair agrees: confirmed; one that does
  // not, or a held one two frames back, is held again.
  m.last_valid = false;
  note_reversal(m, Reversal::held, back, 175);
  constexpr std::int64_t kT176Ns = kT175Ns + 16'666'667;
  EXPECT_EQ(judge_reversal(m, {-0.27, 0.02}, 176, kT176Ns, kDtS, set), Reversal::confirmed);
  EXPECT_EQ(judge_reversal(m, {-0.9, 0.0}, 176, kT176Ns, kDtS, set), Reversal::held);
  EXPECT_EQ(judge_reversal(m, {-0.27, 0.02}, 177, kT175Ns + 33'333'333, kDtS, set), Reversal::held);
  // Anything else the pair says forgets the held one.
  note_reversal(m, Reversal::none, {1.2, 0.0}, 176);
  EXPECT_EQ(judge_reversal(m, {-0.27, 0.02}, 177, kT175Ns + 33'333'333, kDtS, set), Reversal::held);
}

TEST(SensorPattern, SharpGroundHardlyTeachesThePixelPattern) {
  // Frames alternate between sharp ground (20 grey levels RMS) and blurred
  // ground (2 grey levels). A plain mean of the 100 frames would keep
  // sqrt(50 * 20^2 + 50 * 2^2) / 100 = 1.4 grey levels RMS of ground in the
  // pattern, against 2.3 of offsets; weighted by the inverse of each frame's
  // ground variance the blurred frames rule and ~0.3 stays.
  const cv::Size size(160, 120);
  SensorPattern p(size);
  cv::Mat pixel_offsets(size, CV_32F);
  cv::RNG rng(7);
  rng.fill(pixel_offsets, cv::RNG::UNIFORM, -4.0, 4.0);
  for (int i = 0; i < 100; ++i) {
    cv::Mat ground(size, CV_32F);
    rng.fill(ground, cv::RNG::NORMAL, 100.0, i % 2 == 0 ? 20.0 : 2.0);
    cv::Mat gray;
    cv::Mat(ground + pixel_offsets).convertTo(gray, CV_8U);
    p.learn_pixels(gray, cv::mean(gray)[0]);
  }
  const cv::Mat expected = pixel_offsets - cv::mean(pixel_offsets)[0];
  const double err_rms = cv::norm(p.pixels(), expected, cv::NORM_L2) / std::sqrt(size.area());
  EXPECT_LT(err_rms, 0.6);
}

}  // namespace
}  // namespace gvs::dsp
