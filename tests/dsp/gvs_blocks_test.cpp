// Unit tests of the gvs estimator's building blocks on synthetic frames
// (gvs_synth.hpp): phase correlation, streak axis, streak length, double
// image, frame checks.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <utility>
#include <vector>

#include "gvs/dsp/blur_analysis.hpp"
#include "gvs/dsp/frame_check.hpp"
#include "gvs/dsp/gvs_settings.hpp"
#include "gvs/dsp/vocabulary.hpp"
#include "gvs/dsp/phase_correlation.hpp"
#include "gvs/dsp/spectrum.hpp"
#include "gvs_synth.hpp"

namespace gvs::dsp {
namespace {

const cv::Size kFrame(512, 384);

const cv::Mat& texture() {
  static const cv::Mat tex = test::make_texture(1024, 7);
  return tex;
}

/// Axis angle in image axes, atan2(u_col, u_row), wrapped to (-90, 90].
double axis_deg(double u_row, double u_col) { return wrap_axis_deg(rad_to_deg(std::atan2(u_col, u_row))); }

struct ShiftCase {
  double d_row;
  double d_col;
};

class PhaseCorrelationShift : public ::testing::TestWithParam<ShiftCase> {};

TEST_P(PhaseCorrelationShift, RecoversSubPixelShiftAndSign) {
  const ShiftCase s = GetParam();
  test::Sensor sensor;
  const cv::Mat a = test::render_frame(texture(), kFrame, 10.0, 20.0, 0, 0, 0, 0, test::continuous(0), sensor, 1);
  const cv::Mat b = test::render_frame(texture(), kFrame, 10.0 + s.d_row, 20.0 + s.d_col, 0, 0, 0, 0,
                                       test::continuous(0), sensor, 2);
  WindowedSpectrum spectrum(kFrame);
  cv::Mat fa;
  cv::Mat fb;
  spectrum.compute(a, fa);
  spectrum.compute(b, fb);
  PhaseCorrelator pc(kFrame);
  const ImageShift shift = pc.correlate(fa, fb, 1.5, 200.0);
  ASSERT_TRUE(shift.found);
  EXPECT_NEAR(shift.d_row_px, s.d_row, 0.08);
  EXPECT_NEAR(shift.d_col_px, s.d_col, 0.08);
  EXPECT_GT(shift.peak_to_rms, 20.0);
}

INSTANTIATE_TEST_SUITE_P(Shifts, PhaseCorrelationShift,
                         ::testing::Values(ShiftCase{23.25, -7.5}, ShiftCase{-60.0, 40.75},
                                           ShiftCase{150.4, 3.3}, ShiftCase{2.5, 0.0},
                                           ShiftCase{-0.3, 95.6}));

TEST(PhaseCorrelation, FixedPatternNoiseDoesNotWinAtZeroShift) {
  // Weak texture, strong fixed-pattern noise: the zero-lag peak is the highest
  // on the surface, but it is excluded and the true shift is found.
  test::Sensor sensor;
  sensor.contrast_grey = 6.0;
  sensor.fpn_grey = 6.0;
  const cv::Mat a = test::render_frame(texture(), kFrame, 0, 0, 0, 0, 0, 0, test::continuous(0), sensor, 1);
  const cv::Mat b = test::render_frame(texture(), kFrame, 12.5, -4.0, 0, 0, 0, 0, test::continuous(0), sensor, 2);
  WindowedSpectrum spectrum(kFrame);
  cv::Mat fa;
  cv::Mat fb;
  spectrum.compute(a, fa);
  spectrum.compute(b, fb);
  PhaseCorrelator pc(kFrame);
  const ImageShift shift = pc.correlate(fa, fb, 1.5, 200.0);
  ASSERT_TRUE(shift.found);
  EXPECT_GT(pc.surface().at<float>(0, 0), 0.5 * shift.peak);  // the FPN peak is really there
  EXPECT_NEAR(shift.d_row_px, 12.5, 0.15);
  EXPECT_NEAR(shift.d_col_px, -4.0, 0.15);
}

struct StreakCase {
  double angle_deg;  // image axes: atan2(col, row)
  double length_px;
};

class StreakAnalysis : public ::testing::TestWithParam<StreakCase> {};

TEST_P(StreakAnalysis, AxisAndLength) {
  const StreakCase s = GetParam();
  const double a = deg_to_rad(s.angle_deg);
  test::Sensor sensor;
  const cv::Mat img = test::render_frame(texture(), kFrame, 0, 0, 0, std::cos(a), std::sin(a), 0,
                                         test::continuous(s.length_px), sensor, 3);
  WindowedSpectrum spectrum(kFrame);
  cv::Mat f;
  spectrum.compute(img, f);
  BlurAnalyzer blur(kFrame);
  const StreakAxis axis = blur.streak_axis(f);
  const double err_axis = wrap_axis_deg(axis_deg(axis.u_row, axis.u_col) - s.angle_deg);
  std::printf("streak %5.1f deg %5.1f px: axis err %+.3f deg, anisotropy %.2f\n", s.angle_deg,
              s.length_px, err_axis, axis.anisotropy);
  EXPECT_LT(std::abs(err_axis), s.length_px >= 30 ? 0.3 : 1.0);
  EXPECT_GT(axis.anisotropy, 0.3);

  const StreakLength len = blur.streak_length(f, axis, 5.0, 160.0);
  ASSERT_TRUE(len.found);
  const double err_len = len.length_px / s.length_px - 1.0;
  const double err_peak_axis = wrap_axis_deg(axis_deg(len.d_row_px, len.d_col_px) - s.angle_deg);
  std::printf("   length %.2f px (err %+.2f %%), depth %.2f, peak axis err %+.3f deg\n", len.length_px,
              100.0 * err_len, len.depth, err_peak_axis);
  // Under 20 px the trough at L sits on the flank of the central lobe, which
  // the 0.4 rad/px roll-off widens: about -0.1 px on this fine texture at
  // 12 px (blur_length.cpp), hence 1.5 % under 20 px and 1 % above.
  EXPECT_LT(std::abs(err_len), s.length_px < 20.0 ? 0.015 : 0.01);
  EXPECT_GT(len.depth, 0.1);

  // The power cepstrum reads the same end (it vouches for faint ones; the
  // estimator asks the two to agree within cepstrum_max_disagreement, 3 %). Its first zero lies at
  // |k.u| = 2 pi / L: from ~25 px several zeros fall in the band.
  if (s.length_px >= 25.0) {
    const StreakLength cep = blur.streak_length_cepstral(f, axis, 5.0, 160.0);
    ASSERT_TRUE(cep.found);
    std::printf("   cepstrum %.2f px (err %+.2f %%)\n", cep.length_px, 100.0 * (cep.length_px / s.length_px - 1.0));
    EXPECT_LT(std::abs(cep.length_px / s.length_px - 1.0), 0.01);
  }
}

INSTANTIATE_TEST_SUITE_P(Angles, StreakAnalysis,
                         ::testing::Values(StreakCase{0.0, 40.0}, StreakCase{17.0, 60.0},
                                           StreakCase{45.0, 25.0}, StreakCase{90.0, 80.0},
                                           StreakCase{-62.5, 120.0}, StreakCase{133.0, 12.0}));

// Two streak ends as deep (here two equally bright exposures of one patch,
// 60 and 75 px long): the surface alone cannot tell which is the streak's.
// They are reported as rivals; the expected length chooses which one is
// returned, and the estimator asks the cepstrum (streak_end.cpp).
TEST(StreakAnalysis, TwoEndsAsDeepAreRivals) {
  const double a = deg_to_rad(17.0);
  const test::Sensor sensor;
  WindowedSpectrum spectrum(kFrame);
  BlurAnalyzer blur(kFrame);
  cv::Mat f;
  const cv::Mat one = test::render_frame(texture(), kFrame, 0, 0, 0, std::cos(a), std::sin(a), 0,
                                         test::continuous(75.0), sensor, 5);
  spectrum.compute(one, f);
  const StreakAxis axis_one = blur.streak_axis(f);
  const StreakLength single = blur.streak_length(f, axis_one, 20.0, 160.0, 72.0);
  ASSERT_TRUE(single.found);
  EXPECT_NEAR(single.length_px, 75.0, 0.75);
  EXPECT_EQ(single.rivals, 0);

  const std::vector<test::Pulse> two = {{0.0, 60.0, 1.0}, {0.0, 75.0, 1.0}};
  const cv::Mat both = test::render_frame(texture(), kFrame, 0, 0, 0, std::cos(a), std::sin(a), 0, two, sensor, 5);
  spectrum.compute(both, f);
  const StreakAxis axis = blur.streak_axis(f);
  for (const double expected_px : {60.0, 75.0}) {
    const StreakLength len = blur.streak_length(f, axis, 20.0, 160.0, expected_px);
    ASSERT_TRUE(len.found);
    std::printf("ends at 60 and 75 px, expected %.0f: %.2f px, %d rival(s)\n", expected_px, len.length_px, len.rivals);
    EXPECT_NEAR(len.length_px, expected_px, 1.0);
    EXPECT_GE(len.rivals, 1);
  }
  // The rival ends read again on the same autocorrelation, after the
  // cepstrum has run (streak_end.cpp asks it in between): as a fresh search.
  const StreakLength first = blur.streak_length(f, axis, 20.0, 160.0, 60.0);
  (void)blur.streak_length_cepstral(f, axis, 20.0, 160.0);
  const StreakLength again = blur.streak_length_again(20.0, 160.0, 75.0);
  const StreakLength fresh = blur.streak_length(f, axis, 20.0, 160.0, 75.0);
  ASSERT_TRUE(again.found);
  EXPECT_NEAR(first.length_px, 60.0, 1.0);
  EXPECT_EQ(again.length_px, fresh.length_px);
  EXPECT_EQ(again.significance, fresh.significance);
  EXPECT_EQ(again.background, fresh.background);
  EXPECT_EQ(again.rivals, fresh.rivals);
}

// The anisotropy a streak of L px would give, predicted from the ground's
// own spectrum on the line k.u = 0 (blur_consistency.cpp), is what the
// frame shows, on fine and on coarse grain alike; the two grounds differ
// (the finer, the more elongated at the same L), and each streak passes the
// cold-start rule (no more elongated than a streak twice as long would be).
// The cepstrum's end stands out of its ray (StreakLength::significance, as
// the streak end's) where a streak ends within the range it looks at; under
// a streak far longer, its deepest point is only the least positive one.
TEST(StreakAnalysis, TheCepstrumsEndStandsOutWhereTheStreakEndsInItsRange) {
  const double a = deg_to_rad(17.0);
  const test::Sensor sensor;
  WindowedSpectrum spectrum(kFrame);
  BlurAnalyzer blur(kFrame);
  const GvsEstimatorSettings set;
  cv::Mat f;
  double significance[2] = {0.0, 0.0};
  const double lengths_px[2] = {90.0, 600.0};
  for (int i = 0; i < 2; ++i) {
    const cv::Mat frame = test::render_frame(texture(), kFrame, 0, 0, 0, std::cos(a), std::sin(a), 0,
                                             test::continuous(lengths_px[i]), sensor, 5);
    spectrum.compute(frame, f);
    const StreakAxis axis = blur.streak_axis(f);
    const StreakLength cep = blur.streak_length_cepstral(f, axis, 20.0, 160.0);
    significance[i] = cep.found ? cep.significance : 0.0;
    std::printf("   %.0f px streak: cepstrum %.1f px, significance %.2f\n", lengths_px[i], cep.length_px,
                significance[i]);
  }
  EXPECT_GE(significance[0], set.min_streak_significance);
  EXPECT_LT(significance[1], set.min_streak_significance);
}

TEST(StreakAnalysis, PredictedAnisotropyFollowsTheGround) {
  const double a = deg_to_rad(17.0);
  const test::Sensor sensor;
  WindowedSpectrum spectrum(kFrame);
  BlurAnalyzer blur(kFrame);
  cv::Mat f;
  const cv::Mat coarse = test::make_texture(1024, 11, 3.0);
  double predicted_40[2] = {0.0, 0.0};
  int i = 0;
  for (const cv::Mat* ground : {&texture(), &coarse}) {
    for (const double length_px : {20.0, 40.0, 80.0}) {
      const cv::Mat img = test::render_frame(*ground, kFrame, 0, 0, 0, std::cos(a), std::sin(a), 0,
                                             test::continuous(length_px), sensor, 7);
      spectrum.compute(img, f);
      const StreakAxis axis = blur.streak_axis(f);
      const double predicted = blur.streak_anisotropy(f, axis, length_px);
      std::printf("grain %d, %3.0f px: anisotropy %.4f, predicted %.4f (2L: %.4f)\n", i, length_px, axis.anisotropy,
                  predicted, blur.streak_anisotropy(f, axis, 2.0 * length_px));
      EXPECT_NEAR(axis.anisotropy, predicted, 0.03);
      EXPECT_LE(axis.anisotropy, blur.streak_anisotropy(f, axis, 2.0 * length_px));
      if (length_px == 40.0) predicted_40[i] = predicted;
    }
    ++i;
  }
  EXPECT_GT(predicted_40[0], predicted_40[1] + 0.01);
}

// Over many patches of ground, the streak end is found where it is (no
// pull towards lag 0 from the window, no tilt from coarse texture) and
// scatters by a tenth of a pixel.
TEST(StreakAnalysis, LengthOverManyPatchesIsUnbiasedAndPrecise) {
  const double length_px = 60.0;
  const double a = deg_to_rad(17.0);
  // Coarser ground than texture(): grain 3 px with 12 px stones.
  const cv::Mat coarse = test::make_texture(1024, 11, 3.0);
  WindowedSpectrum spectrum(kFrame);
  BlurAnalyzer blur(kFrame);
  cv::Mat f;
  double sum = 0.0;
  double sum_sq = 0.0;
  int n = 0;
  for (int i = 0; i < 16; ++i) {
    const test::Sensor sensor;
    const cv::Mat img = test::render_frame(coarse, kFrame, 23.0 * (i % 4), 31.0 * (i / 4), 0, std::cos(a),
                                           std::sin(a), 0, test::continuous(length_px), sensor,
                                           static_cast<std::uint64_t>(100 + i));
    spectrum.compute(img, f);
    const StreakAxis axis = blur.streak_axis(f);
    const StreakLength len = blur.streak_length(f, axis, 5.0, 160.0);
    ASSERT_TRUE(len.found);
    const double err = len.length_px - length_px;
    sum += err;
    sum_sq += err * err;
    ++n;
  }
  const double mean = sum / n;
  const double sd = std::sqrt(std::max(0.0, sum_sq / n - mean * mean));
  std::printf("streak 60 px over %d patches: mean error %+.3f px, sd %.3f px\n", n, mean, sd);
  // The window's overlap divided out and |k| < 0.2 rad/px dropped keep the
  // mean within a tenth of a pixel (blur_length.cpp).
  EXPECT_LT(std::abs(mean), 0.1);
  EXPECT_LT(sd, 0.1);
}

TEST(SpectrumWindow, TukeyIsFlatInTheMiddleAndTapersAtTheBorders) {
  const std::vector<double> w = tukey_window(101, 0.2);  // tapers over 10 samples each side
  EXPECT_DOUBLE_EQ(w[0], 0.0);
  EXPECT_DOUBLE_EQ(w[100], 0.0);
  EXPECT_NEAR(w[5], 0.5, 1e-12);  // half-way up the taper
  EXPECT_DOUBLE_EQ(w[10], 1.0);
  EXPECT_DOUBLE_EQ(w[50], 1.0);
  EXPECT_DOUBLE_EQ(w[90], 1.0);
  for (std::size_t i = 0; i < w.size(); ++i) EXPECT_DOUBLE_EQ(w[i], w[w.size() - 1 - i]);
  // Taper 1 is the Hann window.
  const std::vector<double> hann = tukey_window(9, 1.0);
  for (int i = 0; i < 9; ++i) EXPECT_NEAR(hann[static_cast<std::size_t>(i)], 0.5 * (1.0 - std::cos(2.0 * kPi * i / 8.0)), 1e-12);
}

TEST(WindowOverlap, IsTheWindowsOverlapWithItselfShifted) {
  const cv::Size size(64, 48);
  const cv::Mat w = spectrum_window(size, CV_64F);
  const WindowOverlap overlap(size);
  double w2 = 0.0;
  for (int r = 0; r < size.height; ++r)
    for (int c = 0; c < size.width; ++c) w2 += w.at<double>(r, c) * w.at<double>(r, c);
  // O(dr, dc) = sum w(x) w(x + t) / sum w^2 over the 2-D window (no wrap).
  for (const auto& [dr, dc] : {std::pair{0, 0}, std::pair{5, 0}, std::pair{0, 17}, std::pair{-9, 30},
                               std::pair{13, -2}}) {
    double sum = 0.0;
    for (int r = 0; r < size.height; ++r) {
      for (int c = 0; c < size.width; ++c) {
        const int r2 = r + dr;
        const int c2 = c + dc;
        if (r2 < 0 || r2 >= size.height || c2 < 0 || c2 >= size.width) continue;
        sum += w.at<double>(r, c) * w.at<double>(r2, c2);
      }
    }
    EXPECT_NEAR(overlap.at(dr, dc), sum / w2, 1e-9) << dr << "," << dc;
    // Lags wrap like the DFT surface: -t is stored at n - t.
    EXPECT_NEAR(overlap.at(dr + size.height, dc - size.width), sum / w2, 1e-9) << dr << "," << dc;
  }
  EXPECT_LT(overlap.at(0, 30), overlap.at(0, 10));
}

TEST(SpectrumWindow, PixelOffsetsAreTakenOutFirst) {
  // A frame plus a per-pixel pattern, with the pattern given: the spectrum of
  // the frame alone (up to float rounding; a contrast that does not clip).
  test::Sensor sensor;
  sensor.contrast_grey = 10.0;
  const cv::Mat clean = test::render_frame(texture(), kFrame, 0, 0, 0, 0, 0, 0, test::continuous(0), sensor, 3);
  cv::Mat pattern(kFrame, CV_32F);
  cv::RNG rng(5);
  for (int r = 0; r < kFrame.height; ++r) {
    for (int c = 0; c < kFrame.width; ++c) pattern.at<float>(r, c) = static_cast<float>(rng.uniform(-4, 5));
  }
  cv::Mat with_pattern;
  cv::Mat clean_f;
  clean.convertTo(clean_f, CV_32F);
  cv::Mat(clean_f + pattern).convertTo(with_pattern, CV_8U);
  WindowedSpectrum spectrum(kFrame);
  cv::Mat f_clean;
  cv::Mat f_taken_out;
  cv::Mat f_left_in;
  spectrum.compute(clean, f_clean);
  spectrum.compute(with_pattern, f_taken_out, pattern);
  spectrum.compute(with_pattern, f_left_in);
  const double scale = cv::norm(f_clean);
  EXPECT_LT(cv::norm(f_taken_out - f_clean) / scale, 1e-5);
  EXPECT_GT(cv::norm(f_left_in - f_clean) / scale, 0.05);  // the pattern does show otherwise
}

TEST(StreakAnalysis, RingGainKeepsTheTextureAndDropsTheNoise) {
  // A dark, long-streaked frame: texture above the noise at low |k| only.
  // ring_gain() keeps those rings and drops the rest, and the axis with it
  // is sharper than without (on the same frames).
  const double a = deg_to_rad(30.0);
  test::Sensor sensor;
  sensor.mean_grey = 10.0;
  sensor.contrast_grey = 2.0;
  sensor.noise_grey = 1.5;
  sensor.fpn_grey = 0.0;
  WindowedSpectrum spectrum(kFrame);
  BlurAnalyzer blur(kFrame);
  cv::Mat f;
  BlurAnalyzer::RingGain gain{};
  double plain_sq = 0.0;
  double gained_sq = 0.0;
  const int frames = 6;
  for (int i = 0; i < frames; ++i) {
    const cv::Mat img = test::render_frame(texture(), kFrame, 37.0 * i, 11.0 * i, 0, std::cos(a), std::sin(a), 0,
                                           test::continuous(150.0), sensor, 40 + static_cast<std::uint64_t>(i));
    spectrum.compute(img, f);
    blur.ring_gain(f, nullptr, 0.0, gain);
    if (i == 0) {
      const auto ring = [](double k) { return static_cast<std::size_t>(k / BlurAnalyzer::kRingWidth); };
      std::printf("ring gain at 0.15 / 0.5 / 1.5 rad/px: %.2f / %.2f / %.2f\n", gain[ring(0.15)], gain[ring(0.5)],
                  gain[ring(1.5)]);
      EXPECT_GT(gain[ring(0.15)], 0.5);
      EXPECT_LT(gain[ring(1.5)], 0.05);
    }
    const StreakAxis plain = blur.refine_axis(f, blur.streak_axis(f), 0.05, 2);
    StreakAxis gained = blur.streak_axis(f, &gain);
    blur.ring_gain(f, &gained, 0.1, gain);
    gained = blur.refine_axis(f, gained, 0.05, 2, false, &gain);
    const double e_plain = wrap_axis_deg(axis_deg(plain.u_row, plain.u_col) - 30.0);
    const double e_gained = wrap_axis_deg(axis_deg(gained.u_row, gained.u_col) - 30.0);
    std::printf("frame %d: texture SNR %.2f, axis off by %.3f deg plain, %.3f deg with the ring gain\n", i,
                plain.texture_snr, e_plain, e_gained);
    plain_sq += e_plain * e_plain;
    gained_sq += e_gained * e_gained;
  }
  const double plain_rms = std::sqrt(plain_sq / frames);
  const double gained_rms = std::sqrt(gained_sq / frames);
  std::printf("axis RMS: %.3f deg plain, %.3f deg with the ring gain\n", plain_rms, gained_rms);
  EXPECT_LT(gained_rms, 0.7 * plain_rms);  // measured 0.21 against 0.41 deg
}

TEST(StreakAnalysis, NoBlurIsIsotropic) {
  test::Sensor sensor;
  const cv::Mat img = test::render_frame(texture(), kFrame, 0, 0, 0, 0, 0, 0, test::continuous(0), sensor, 3);
  WindowedSpectrum spectrum(kFrame);
  cv::Mat f;
  spectrum.compute(img, f);
  BlurAnalyzer blur(kFrame);
  EXPECT_LT(blur.streak_axis(f).anisotropy, 0.1);
}

TEST(DoubleImage, DisplacementAndEnergySign) {
  // Two 1-unit pulses 90 units apart, the first twice as strong, motion at 70 deg.
  const double a = deg_to_rad(70.0);
  test::Sensor sensor;
  const std::vector<test::Pulse> pulses = {{0.0, 1.0, 2.0}, {90.0, 1.0, 1.0}};
  const cv::Mat img = test::render_frame(texture(), kFrame, 0, 0, 0, std::cos(a), std::sin(a), 0,
                                         pulses, sensor, 4);
  WindowedSpectrum spectrum(kFrame);
  cv::Mat f;
  spectrum.compute(img, f);
  BlurAnalyzer blur(kFrame);
  DoubleImage d = blur.double_image(f, 4.0, 170.0);
  ASSERT_TRUE(d.found);
  const double len = std::hypot(d.d_row_px, d.d_col_px);
  EXPECT_NEAR(len, 90.0, 0.2);
  EXPECT_NEAR(wrap_axis_deg(axis_deg(d.d_row_px, d.d_col_px) - 70.0), 0.0, 0.1);
  EXPECT_GT(d.height, 0.2);
  double_image_asymmetry(img, d);
  // d as found points along +70 deg or -110 deg; the asymmetry must say which.
  const bool found_forward = d.d_row_px * std::cos(a) + d.d_col_px * std::sin(a) > 0.0;
  std::printf("double image: %.2f px, height %.2f, asymmetry %+.2f, skewness %.2f\n", len, d.height,
              d.asymmetry, d.skewness);
  EXPECT_GT(d.skewness, 0.3);
  EXPECT_EQ(d.asymmetry > 0.0, found_forward);
  EXPECT_GT(std::abs(d.asymmetry), 0.2);
}

// A dark frame at high gain: faint texture, strong column offsets (constant
// down each column, like a real sensor's column fixed pattern). The column
// pattern correlates at every row lag; the double image must still win.
TEST(DoubleImage, ColumnFixedPatternDoesNotMakeASidePeak) {
  const double a = deg_to_rad(20.0);
  test::Sensor sensor;
  sensor.contrast_grey = 4.0;
  sensor.noise_grey = 2.0;
  const std::vector<test::Pulse> pulses = {{0.0, 1.0, 1.0}, {60.0, 1.0, 1.0}};
  cv::Mat img = test::render_frame(texture(), kFrame, 0, 0, 0, std::cos(a), std::sin(a), 0, pulses, sensor, 5);
  cv::RNG rng(17);
  for (int c = 0; c < img.cols; ++c) {
    const int offset = static_cast<int>(std::lround(rng.gaussian(6.0)));
    for (int r = 0; r < img.rows; ++r) img.at<std::uint8_t>(r, c) = cv::saturate_cast<std::uint8_t>(img.at<std::uint8_t>(r, c) + offset);
  }
  WindowedSpectrum spectrum(kFrame);
  cv::Mat f;
  spectrum.compute(img, f);
  BlurAnalyzer blur(kFrame);
  const DoubleImage d = blur.double_image(f, 4.0, 170.0);
  ASSERT_TRUE(d.found);
  std::printf("double image under column pattern: (%.2f, %.2f) px, height %.2f, second %.2f\n", d.d_row_px,
              d.d_col_px, d.height, d.second_ratio);
  EXPECT_NEAR(std::hypot(d.d_row_px, d.d_col_px), 60.0, 0.3);
  EXPECT_NEAR(wrap_axis_deg(axis_deg(d.d_row_px, d.d_col_px) - 20.0), 0.0, 0.3);
}

TEST(FrameCheck, NamesWhyThereIsNothingToMeasure) {
  cv::Mat dark(kFrame, CV_8UC1, cv::Scalar(1));
  EXPECT_EQ(frame_problem(measure_frame(dark)), Method::dark);
  cv::Mat saturated(kFrame, CV_8UC1, cv::Scalar(255));
  EXPECT_EQ(frame_problem(measure_frame(saturated)), Method::saturated);
  cv::Mat uniform(kFrame, CV_8UC1, cv::Scalar(120));
  EXPECT_EQ(frame_problem(measure_frame(uniform)), Method::no_texture);
  test::Sensor sensor;
  const cv::Mat good = test::render_frame(texture(), kFrame, 0, 0, 0, 0, 0, 0, test::continuous(0), sensor, 5);
  EXPECT_EQ(frame_problem(measure_frame(good)), std::nullopt);
  sensor.mean_grey = 10.0;
  sensor.contrast_grey = 3.0;
  const cv::Mat under = test::render_frame(texture(), kFrame, 0, 0, 0, 0, 0, 0, test::continuous(0), sensor, 5);
  EXPECT_EQ(frame_problem(measure_frame(under)), std::nullopt);
}

}  // namespace
}  // namespace gvs::dsp
