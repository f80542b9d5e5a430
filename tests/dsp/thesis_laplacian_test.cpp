// thesis-laplacian: Laplacian standard deviation falls with blur, and the
// piecewise-exponential inverse model (thesis 5.3).
#include <array>
#include <cmath>
#include <cstdio>

#include <gtest/gtest.h>

#include "gvs/dsp/thesis.hpp"
#include "thesis_synth.hpp"

namespace gvs::dsp {
namespace {

TEST(ThesisLaplacian, StdFallsAsBlurGrows) {
  const cv::Mat texture = test::blob_texture(712, 584, 5);
  thesis::LaplacianBlur lap(0.1);
  double previous = 1e9;
  for (double blur : {0.0, 4.0, 10.0, 25.0, 60.0}) {
    const cv::Mat f = blur > 0.0 ? test::line_blurred_crop(texture, 0.0, blur, 512, 384)
                                 : test::shifted_crop(texture, 0.0, 0.0, 512, 384);
    const double s = lap.lap_std(f);
    std::printf("blur %5.1f px -> lap_std %.3f\n", blur, s);
    EXPECT_LT(s, previous);
    previous = s;
  }
}

TEST(ThesisLaplacian, BadFrameGivesNegativeStd) {
  thesis::LaplacianBlur lap(0.1);
  EXPECT_LT(lap.lap_std(cv::Mat()), 0.0);
  EXPECT_LT(lap.lap_std(cv::Mat(10, 10, CV_32F, cv::Scalar(1.0))), 0.0);
}

// A two-piece model: sigma = 20 exp(-0.2 v) on [0, 5], continuing with
// b = -0.05 on [5, 30].
constexpr double kA0 = 20.0;
constexpr double kB0 = -0.2;
constexpr double kB1 = -0.05;
const std::array<thesis::LaplacianSegment, 2> kModel{
    thesis::LaplacianSegment{0.0, 5.0, kA0, kB0},
    thesis::LaplacianSegment{5.0, 30.0, kA0 * std::exp(kB0 * 5.0) * std::exp(-kB1 * 5.0), kB1}};

TEST(ThesisLaplacian, InverseModelRoundTrips) {
  for (double v : {0.0, 0.5, 2.0, 4.99, 5.0, 7.5, 18.0, 30.0}) {
    const auto& seg = v <= 5.0 ? kModel[0] : kModel[1];
    const double sigma = seg.a * std::exp(seg.b * v);
    const thesis::LaplacianSpeed s = thesis::invert_laplacian_model(sigma, kModel);
    ASSERT_TRUE(s.ok);
    EXPECT_FALSE(s.clamped);
    EXPECT_NEAR(s.speed_mps, v, 1e-9);
    EXPECT_GT(s.quality, 0.0);
  }
}

TEST(ThesisLaplacian, InverseModelClampsOutsideItsRange) {
  const thesis::LaplacianSpeed sharp = thesis::invert_laplacian_model(kA0 * 1.5, kModel);
  ASSERT_TRUE(sharp.ok);
  EXPECT_TRUE(sharp.clamped);
  EXPECT_EQ(sharp.speed_mps, 0.0);
  const thesis::LaplacianSpeed smeared = thesis::invert_laplacian_model(1e-3, kModel);
  ASSERT_TRUE(smeared.ok);
  EXPECT_TRUE(smeared.clamped);
  EXPECT_EQ(smeared.speed_mps, 30.0);
  EXPECT_FALSE(thesis::invert_laplacian_model(-1.0, kModel).ok);
  EXPECT_FALSE(thesis::invert_laplacian_model(5.0, {}).ok);
}

TEST(ThesisLaplacian, InverseModelBridgesARoundingGapAtASwitchingPoint) {
  // Second piece starts 0.05 % below where the first ends.
  std::array<thesis::LaplacianSegment, 2> m = kModel;
  m[1].a *= 0.9995;
  const double end_first = kA0 * std::exp(kB0 * 5.0);
  const thesis::LaplacianSpeed s = thesis::invert_laplacian_model(end_first * 0.99975, m);
  ASSERT_TRUE(s.ok);
  EXPECT_FALSE(s.clamped);
  EXPECT_NEAR(s.speed_mps, 5.0, 0.05);
}

TEST(ThesisLaplacian, FittedModelIsContinuousAndFalling) {
  const auto model = thesis::fitted_laplacian_model();
  ASSERT_FALSE(model.empty()) << "the Laplacian model is not fitted yet: run thesis_laplacian_fit "
                                 "(tests/dsp/thesis_laplacian_fit.cpp) and paste its table into "
                                 "dsp/src/thesis/laplacian.cpp";
  for (std::size_t i = 0; i < model.size(); ++i) {
    EXPECT_LT(model[i].b, 0.0) << "piece " << i << " does not fall with speed";
    EXPECT_LT(model[i].speed_lo_mps, model[i].speed_hi_mps);
    if (i > 0) {
      EXPECT_DOUBLE_EQ(model[i].speed_lo_mps, model[i - 1].speed_hi_mps);
      const double end = model[i - 1].a * std::exp(model[i - 1].b * model[i - 1].speed_hi_mps);
      const double start = model[i].a * std::exp(model[i].b * model[i].speed_lo_mps);
      // The table prints knots to 4 decimals: the pieces meet to about 1e-4.
      EXPECT_NEAR(start, end, 1e-3 * end) << "pieces " << i - 1 << " and " << i << " do not meet";
    }
  }
}

}  // namespace
}  // namespace gvs::dsp
