// dsp::DftPlan (FFTW underneath) against cv::dft, the transform it replaced:
// the same full complex spectrum forwards, the same real image backwards,
// to float rounding.
#include <gtest/gtest.h>

#include <thread>
#include <vector>

#include <opencv2/core.hpp>

#include "gvs/dsp/dft.hpp"

namespace gvs::dsp {
namespace {

cv::Mat random_image(cv::Size size, int seed) {
  cv::Mat m(size, CV_32F);
  cv::RNG rng(static_cast<std::uint64_t>(seed));
  rng.fill(m, cv::RNG::UNIFORM, -100.0, 100.0);
  return m;
}

/// max |a - b| over max |b|: float rounding of a transform is ~1e-6 of its scale.
double relative_error(const cv::Mat& a, const cv::Mat& b) {
  return cv::norm(a, b, cv::NORM_INF) / cv::norm(b, cv::NORM_INF);
}

class DftSizes : public ::testing::TestWithParam<cv::Size> {};

TEST_P(DftSizes, ForwardIsCvDftsFullComplexSpectrum) {
  const cv::Mat image = random_image(GetParam(), 1);
  cv::Mat expected;
  cv::dft(image, expected, cv::DFT_COMPLEX_OUTPUT);
  DftPlan plan(DftPlan::Direction::forward_real_to_complex, GetParam());
  cv::Mat spectrum;
  plan.run(image, spectrum);
  ASSERT_EQ(spectrum.type(), CV_32FC2);
  ASSERT_EQ(spectrum.size(), GetParam());
  EXPECT_LT(relative_error(spectrum, expected), 1e-5);
}

TEST_P(DftSizes, HalfForwardWritesTheFullSpectrumsFirstColumnsAndNoOthers) {
  const cv::Mat image = random_image(GetParam(), 3);
  cv::Mat full;
  DftPlan(DftPlan::Direction::forward_real_to_complex, GetParam()).run(image, full);
  const cv::Scalar untouched(7.0, -7.0);
  cv::Mat half(GetParam(), CV_32FC2, untouched);
  DftPlan plan(DftPlan::Direction::forward_real_to_half_complex, GetParam());
  plan.run(image, half);
  const int half_cols = GetParam().width / 2 + 1;
  const cv::Rect written(0, 0, half_cols, GetParam().height);
  EXPECT_EQ(cv::norm(half(written), full(written), cv::NORM_INF), 0.0) << "the same FFTW output, copied";
  if (half_cols < GetParam().width) {
    const cv::Mat rest = half(cv::Rect(half_cols, 0, GetParam().width - half_cols, GetParam().height));
    EXPECT_EQ(cv::norm(rest, cv::Mat(rest.size(), CV_32FC2, untouched), cv::NORM_INF), 0.0)
        << "columns past cols/2 written";
  }
}

TEST_P(DftSizes, InverseIsCvDftsScaledRealOutput) {
  // Any complex spectrum, not only a real image's: both read the columns
  // 0 .. cols/2. (A single column, which cv::dft transforms as a 1-D signal
  // and reads by rows, agrees on a real image's spectrum only.)
  cv::Mat spectrum(GetParam(), CV_32FC2);
  cv::RNG(2).fill(spectrum, cv::RNG::UNIFORM, -100.0, 100.0);
  if (GetParam().width == 1) cv::dft(random_image(GetParam(), 2), spectrum, cv::DFT_COMPLEX_OUTPUT);
  cv::Mat expected;
  cv::dft(spectrum, expected, cv::DFT_INVERSE | cv::DFT_REAL_OUTPUT | cv::DFT_SCALE);
  DftPlan plan(DftPlan::Direction::inverse_complex_to_real);  // plans on the first run
  cv::Mat image;
  plan.run(spectrum, image);
  ASSERT_EQ(image.type(), CV_32FC1);
  EXPECT_LT(relative_error(image, expected), 1e-5);
}

TEST_P(DftSizes, InverseUndoesForward) {
  const cv::Mat image = random_image(GetParam(), 3);
  DftPlan forward(DftPlan::Direction::forward_real_to_complex, GetParam());
  DftPlan inverse(DftPlan::Direction::inverse_complex_to_real, GetParam());
  cv::Mat spectrum;
  cv::Mat back;
  forward.run(image, spectrum);
  inverse.run(spectrum, back);
  EXPECT_LT(relative_error(back, image), 1e-5);
}

// The estimator's sizes (frame, pair half window, a small one) and odd ones.
INSTANTIATE_TEST_SUITE_P(Sizes, DftSizes,
                         ::testing::Values(cv::Size(512, 384), cv::Size(320, 384), cv::Size(128, 96),
                                           cv::Size(33, 17), cv::Size(1, 8)));

TEST(DftPlan, TakesARegionOfALargerImage) {
  // Not continuous: copied into the plan's own array first.
  const cv::Mat frame = random_image({512, 384}, 4);
  const cv::Mat region = frame(cv::Rect(96, 0, 320, 384));
  ASSERT_FALSE(region.isContinuous());
  cv::Mat expected;
  cv::dft(region.clone(), expected, cv::DFT_COMPLEX_OUTPUT);
  DftPlan plan(DftPlan::Direction::forward_real_to_complex, region.size());
  cv::Mat spectrum;
  plan.run(region, spectrum);
  EXPECT_LT(relative_error(spectrum, expected), 1e-5);
  // ... and writes the inverse into a region too.
  cv::Mat canvas(384, 512, CV_32F, cv::Scalar(0));
  cv::Mat out = canvas(cv::Rect(96, 0, 320, 384));
  DftPlan inverse(DftPlan::Direction::inverse_complex_to_real, region.size());
  inverse.run(spectrum, out);
  EXPECT_LT(relative_error(out, region), 1e-5);
  EXPECT_EQ(cv::countNonZero(canvas(cv::Rect(0, 0, 96, 384))), 0);
}

TEST(DftPlan, ReplansWhenTheSizeChanges) {
  DftPlan plan(DftPlan::Direction::forward_real_to_complex, {64, 48});
  for (const cv::Size size : {cv::Size(64, 48), cv::Size(40, 30), cv::Size(64, 48)}) {
    const cv::Mat image = random_image(size, size.width);
    cv::Mat expected;
    cv::dft(image, expected, cv::DFT_COMPLEX_OUTPUT);
    cv::Mat spectrum;
    plan.run(image, spectrum);
    EXPECT_LT(relative_error(spectrum, expected), 1e-5) << size;
  }
}

TEST(DftPlan, PlansAndRunsOnSeveralThreadsAtOnce) {
  // FFTW's planner is not thread-safe; DftPlan serialises it (dft.cpp).
  const cv::Mat image = random_image({160, 120}, 5);
  cv::Mat expected;
  cv::dft(image, expected, cv::DFT_COMPLEX_OUTPUT);
  std::vector<double> errors(8, 1.0);
  std::vector<std::thread> threads;
  for (std::size_t t = 0; t < errors.size(); ++t) {
    threads.emplace_back([&, t] {
      cv::Mat spectrum;
      for (int i = 0; i < 20; ++i) {
        DftPlan plan(DftPlan::Direction::forward_real_to_complex, image.size());
        plan.run(image, spectrum);
      }
      errors[t] = relative_error(spectrum, expected);
    });
  }
  for (std::thread& th : threads) th.join();
  for (const double e : errors) EXPECT_LT(e, 1e-5);
}

TEST(DftPlan, RefusesAnEmptyImage) {
  EXPECT_THROW(DftPlan(DftPlan::Direction::forward_real_to_complex, cv::Size(0, 4)), std::invalid_argument);
}

}  // namespace
}  // namespace gvs::dsp
