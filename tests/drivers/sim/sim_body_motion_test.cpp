// Body motion in the simulator (docs/simulator.md, "Body motion"): the
// camera's height scales the view, pitch and roll make the scale vary across
// the frame (ISO 8855 signs), the pose is followed through the exposure, the
// truth records it, and a run without body motion renders as before.
// Every scale here is measured from the images (phase correlation of
// patches), not taken from the projection's formula.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <tuple>
#include <vector>

#include "gvs/drivers/simulator.hpp"
#include "sim_test_util.hpp"

namespace gvs::drivers::sim::test {
namespace {

constexpr double kNominalMm = 60.0;  // SimulatorConfig::camera_height_mm
constexpr double kRc = (384 - 1) / 2.0;
constexpr double kCc = (512 - 1) / 2.0;
constexpr double kDeg = std::numbers::pi / 180.0;

/// A standing car (no blur) with a constant body pose; noise-free sensor.
Scenario standing(const BodyPose& pose, bool with_body = true) {
  Scenario s = constant_motion_scenario(0.0, 0.0);
  if (with_body) s.body = [pose](double) { return pose; };
  return s;
}

cv::Mat frame(const BodyPose& pose, bool with_body = true) {
  Simulator sim(clean_config(), standing(pose, with_body));
  return render(sim, 2, continuous(1000));
}

/// Shift of the texture from `a` to `b` in a 96 px patch centred (about) at
/// (kRc + dr, kCc + dc); returns the patch centre relative to the image centre.
struct PatchShift {
  double r = 0.0;
  double c = 0.0;
  Shift s;
};
PatchShift patch_shift(const cv::Mat& a, const cv::Mat& b, double dr, double dc) {
  constexpr int kHalf = 48;
  const int r0 = static_cast<int>(kRc + dr) - kHalf + 1;
  const int c0 = static_cast<int>(kCc + dc) - kHalf + 1;
  const cv::Rect box(c0, r0, 2 * kHalf, 2 * kHalf);
  return {r0 + kHalf - 0.5 - kRc, c0 + kHalf - 0.5 - kCc, measure_shift(a(box), b(box))};
}

/// Zoom of b against a about the image centre, found by resampling a
/// (bicubic) at zooms around 1 and keeping the one closest to b (RMS over
/// the frame without a 60 px border): coarse steps of 0.002, then 0.0001.
double best_zoom(const cv::Mat& a, const cv::Mat& b) {
  const cv::Rect inner(60, 60, a.cols - 120, a.rows - 120);
  const auto error = [&](double z) {
    cv::Mat warped;
    const cv::Mat m = (cv::Mat_<double>(2, 3) << z, 0.0, kCc * (1.0 - z), 0.0, z, kRc * (1.0 - z));
    cv::warpAffine(a, warped, m, a.size(), cv::INTER_CUBIC);
    return cv::norm(warped(inner), b(inner), cv::NORM_L2);
  };
  double best = 1.0;
  double best_error = error(1.0);
  for (const auto& [from, to, step] : {std::tuple{0.8, 1.2, 0.002}, std::tuple{-0.002, 0.002, 0.0001}}) {
    const double centre = step < 0.001 ? best : 0.0;
    for (double z = centre + from; z <= centre + to + 1e-12; z += step) {
      const double e = error(z);
      if (e < best_error) {
        best_error = e;
        best = z;
      }
    }
  }
  return best;
}

/// Local zoom along one image axis in a band: slope of the shift along
/// `along_cols` (column shift against column offset, in a band of rows at
/// `band` px from the centre) or down the rows (row shift against row offset,
/// in a band of columns), with a free translation. For the small zooms of a
/// tilt (about 1 %); larger ones bias phase correlation (hence best_zoom).
double band_zoom(const cv::Mat& a, const cv::Mat& b, bool along_cols, double band) {
  std::vector<double> x, y;
  for (const double o : along_cols ? std::vector<double>{-190, -95, 0, 95, 190}
                                   : std::vector<double>{-130, -65, 0, 65, 130}) {
    const PatchShift p = along_cols ? patch_shift(a, b, band, o) : patch_shift(a, b, o, band);
    x.push_back(along_cols ? p.c : p.r);
    y.push_back(along_cols ? p.s.d_col : p.s.d_row);
  }
  double mx = 0.0, my = 0.0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    mx += x[i] / static_cast<double>(x.size());
    my += y[i] / static_cast<double>(y.size());
  }
  double sxy = 0.0, sxx = 0.0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    sxy += (x[i] - mx) * (y[i] - my);
    sxx += (x[i] - mx) * (x[i] - mx);
  }
  return 1.0 + sxy / sxx;
}

TEST(SimBodyMotion, NoBodyMotionAndANominalLevelBodyRenderTheSameFrame) {
  // A body function that keeps the nominal height and level must give the
  // frame of a scenario without one, bit for bit (the datasets of runs
  // without body motion stay what they were).
  const cv::Mat none = frame({}, /*with_body=*/false);
  const cv::Mat nominal = frame({});
  EXPECT_EQ(cv::norm(none, nominal, cv::NORM_INF), 0.0);
  // ... and a millimetre of heave does not.
  EXPECT_GT(cv::norm(none, frame({1.0, 0.0, 0.0}), cv::NORM_INF), 10.0);
}

TEST(SimBodyMotion, TextureSpacingFollowsTheHeight) {
  // A ground point at offset p from the image centre is seen at
  // p H0 / H: the view's scale (mm per px) is proportional to the height.
  const cv::Mat level = frame({});
  for (const double heave_mm : {5.0, -5.0, 0.5, 10.0}) {
    const double measured = best_zoom(level, frame({heave_mm, 0.0, 0.0}));
    EXPECT_NEAR(measured, kNominalMm / (kNominalMm + heave_mm), 0.0003) << "heave " << heave_mm << " mm";
  }
}

TEST(SimBodyMotion, PitchNoseDownMakesTheRearOfTheFrameCoarser) {
  // ISO 8855: positive pitch = nose down; the camera's axis turns backwards,
  // so the rays at the rear of the view (bottom rows) meet the ground
  // farther away: more mm per px at the bottom than at the top. Across the
  // rows the lateral scale changes by about 2 tan(pitch) u, u = 0.2 at
  // 120 px from the centre (12 mm at 60 mm): 1.05 % at 1.5 deg.
  const cv::Mat level = frame({});
  for (const double pitch_deg : {1.5, -1.5}) {
    const cv::Mat tilted = frame({0.0, pitch_deg, 0.0});
    const double top = band_zoom(level, tilted, /*along_cols=*/true, -120.0);
    const double bottom = band_zoom(level, tilted, /*along_cols=*/true, 120.0);
    // Image zoom is the inverse of mm per px: bottom / top in mm per px = top / bottom in zoom.
    const double coarser_at_rear = top / bottom;
    const double first_order = 1.0 + 2.0 * std::tan(pitch_deg * kDeg) * 0.2;
    EXPECT_NEAR(coarser_at_rear, first_order, 0.0025) << "pitch " << pitch_deg << " deg";
    EXPECT_EQ(coarser_at_rear > 1.0, pitch_deg > 0.0) << "pitch " << pitch_deg << " deg";
  }
}

TEST(SimBodyMotion, RollRightSideDownMakesTheLeftOfTheFrameCoarser) {
  // ISO 8855: positive roll = right side down; the camera's axis turns to
  // the left (image columns grow to the right), so the left of the view is
  // farther: more mm per px at the left than at the right (about
  // 2 tan(roll) u, u = 190 px * 0.1 / 60 = 0.317: 1.1 % at 1 deg).
  const cv::Mat level = frame({});
  for (const double roll_deg : {1.0, -1.0}) {
    const cv::Mat tilted = frame({0.0, 0.0, roll_deg});
    const double left = band_zoom(level, tilted, /*along_cols=*/false, -190.0);
    const double right = band_zoom(level, tilted, /*along_cols=*/false, 190.0);
    const double coarser_at_left = right / left;
    const double first_order = 1.0 + 2.0 * std::tan(roll_deg * kDeg) * (190.0 * 0.1 / kNominalMm);
    EXPECT_NEAR(coarser_at_left, first_order, 0.0025) << "roll " << roll_deg << " deg";
    EXPECT_EQ(coarser_at_left > 1.0, roll_deg > 0.0) << "roll " << roll_deg << " deg";
  }
}

TEST(SimBodyMotion, BlurWhileHeavingAndTiltingIsTheAverageOfSnapshots) {
  // The pose is followed through the exposure, knot by knot, not held at
  // mid-exposure: moving and rising 200 mm/s (a kerb strike: 10 mm in 50 ms
  // peaks at 375 mm/s) while pitching at 50 deg/s, the 3 ms frame must be the
  // mean of 150 sharp 20 us snapshots (0.6 mm of heave: 1 % of scale, 2.5 px
  // at the corners; held constant it would differ by that much).
  SimulatorConfig c = clean_config();
  c.sensor.target_mean_dn = 55.0;  // no snapshot saturates (see SimExposure)
  Scenario s = constant_motion_scenario(0.6, 0.2);
  const double t0 = 5.0 / c.fps;
  s.body = [t0](double t) { return BodyPose{200.0 * (t - t0), 1.2 + 50.0 * (t - t0), -0.8}; };
  Simulator sim(c, s);
  const cv::Mat blurred = render(sim, 5, continuous(3000));
  cv::Mat sum = cv::Mat::zeros(blurred.size(), CV_64F);
  constexpr int kSnapshots = 150;
  for (int k = 0; k < kSnapshots; ++k) {
    cv::Mat f;
    render(sim, 5, strobe(20.0 * k, 20.0)).convertTo(f, CV_64F);
    sum += f;
  }
  const cv::Mat mean = sum / kSnapshots;
  cv::Mat b;
  blurred.convertTo(b, CV_64F);
  const cv::Rect inner(8, 8, b.cols - 16, b.rows - 16);
  cv::Scalar mu, sd_blur, sd_diff, sd_held;
  cv::meanStdDev(b(inner), mu, sd_blur);
  cv::meanStdDev(b(inner) - mean(inner), mu, sd_diff);
  EXPECT_LT(sd_diff[0], 0.8) << "blurred frame std " << sd_blur[0];
  EXPECT_GT(sd_blur[0], 5.0);
  // Holding the pose at mid-exposure instead (the same motion, a constant body):
  Scenario held = constant_motion_scenario(0.6, 0.2);
  held.body = [](double) { return BodyPose{0.3, 1.2 + 0.075, -0.8}; };
  Simulator held_sim(c, held);
  cv::Mat h;
  render(held_sim, 5, continuous(3000)).convertTo(h, CV_64F);
  cv::meanStdDev(h(inner) - mean(inner), mu, sd_held);
  EXPECT_GT(sd_held[0], 2.0 * sd_diff[0]) << "exact " << sd_diff[0];
}

TEST(SimBodyMotion, TruthRecordsTheBodyAtMidExposure) {
  SimulatorConfig c;
  c.scenario = "const";
  c.body = "ride";
  c.seconds = 2.0;
  c.fps = 20.0;
  Simulator sim(c);
  EXPECT_TRUE(sim.has_body_motion());
  SimFrame f;
  double lowest = 1e9, highest = -1e9;
  while (sim.next(f)) {
    ASSERT_TRUE(f.truth.height_mm && f.truth.pitch_deg && f.truth.roll_deg);
    const double t_mid = static_cast<double>(f.truth.t_ns) * 1e-9;
    const BodyPose b = sim.trajectory().body(t_mid);
    EXPECT_NEAR(*f.truth.height_mm, kNominalMm + b.heave_mm, 1e-6);
    EXPECT_NEAR(*f.truth.pitch_deg, b.pitch_deg, 1e-9);
    EXPECT_NEAR(*f.truth.roll_deg, b.roll_deg, 1e-9);
    lowest = std::min(lowest, *f.truth.height_mm);
    highest = std::max(highest, *f.truth.height_mm);
  }
  EXPECT_LT(lowest, kNominalMm - 2.0);   // it heaves ...
  EXPECT_GT(highest, kNominalMm + 2.0);  // ... both ways
  // Without body motion the truth has no body fields at all.
  c.body = "flat";
  Simulator flat(c);
  EXPECT_FALSE(flat.has_body_motion());
  ASSERT_TRUE(flat.next(f));
  EXPECT_FALSE(f.truth.height_mm || f.truth.pitch_deg || f.truth.roll_deg);
}

TEST(SimBodyMotion, RideFollowsTheScenarioLikeACar) {
  const Scenario heave = with_body_motion(make_scenario("const"), "heave");
  const Scenario accel = with_body_motion(make_scenario("accel"), "ride");
  const Scenario spin = with_body_motion(make_scenario("spin"), "ride");
  const Scenario skidpad = with_body_motion(make_scenario("skidpad"), "ride");
  const Scenario crawl = with_body_motion(make_scenario("crawl"), "ride");
  // Heave only: within +-5 mm, level, and it uses most of that.
  double peak = 0.0;
  for (double t = 0.0; t < 9.0; t += 0.001) {
    const BodyPose b = heave.body(t);
    ASSERT_LE(std::abs(b.heave_mm), 5.0);
    ASSERT_EQ(b.pitch_deg, 0.0);
    ASSERT_EQ(b.roll_deg, 0.0);
    peak = std::max(peak, std::abs(b.heave_mm));
  }
  EXPECT_GT(peak, 4.0);
  // Accelerating (12 m/s^2 at 3.5 s) lifts the nose: negative pitch;
  // sliding forwards and slowing at 4.5 m/s^2 drops it, and once the car
  // has turned round (sliding backwards, still slowing) lifts it again.
  EXPECT_LT(accel.body(3.5).pitch_deg, -0.5);
  // Braking at 2.1 g from 100 km/h: the nose down by more than a degree.
  EXPECT_GT(with_body_motion(make_scenario("brake"), "ride").body(1.75).pitch_deg, 1.2);
  EXPECT_GT(spin.body(1.2).pitch_deg, 0.2);
  EXPECT_LT(spin.body(3.5).pitch_deg, -0.2);
  // Turning left on the skidpad (1.6 g) rolls the body onto its right side.
  EXPECT_GT(skidpad.body(5.0).roll_deg, 0.6);
  // The kerb at 1.5 s: up 10 mm in 50 ms, gone 150 ms later.
  for (const Scenario* s : {&accel, &spin, &skidpad}) {
    EXPECT_NEAR(s->body(1.55).heave_mm - heave.body(1.55).heave_mm, 10.0, 1e-9);
    EXPECT_NEAR(s->body(1.70).heave_mm - heave.body(1.70).heave_mm, 0.0, 1e-9);
    EXPECT_NEAR(s->body(1.45).heave_mm - heave.body(1.45).heave_mm, 0.0, 1e-9);
  }
  // Limits: 1.5 deg of pitch, 1 deg of roll (plus the kerb's 0.5 deg).
  for (const Scenario* s : {&accel, &spin, &skidpad, &crawl}) {
    for (double t = 0.0; t < s->length_s; t += 0.002) {
      const BodyPose b = s->body(t);
      ASSERT_LT(std::abs(b.pitch_deg), 1.5) << s->name << " t " << t;
      ASSERT_LT(std::abs(b.roll_deg), 1.5) << s->name << " t " << t;
    }
  }
  EXPECT_THROW((void)with_body_motion(make_scenario("const"), "bumpy"), std::invalid_argument);
}

}  // namespace
}  // namespace gvs::drivers::sim::test
