// The VelocityEstimator contract for the four thesis estimators: registered
// by name, never throw, bad frames give a reason word and quality 0.
#include <algorithm>
#include <string>

#include <gtest/gtest.h>

#include "gvs/dsp/thesis.hpp"
#include "thesis_synth.hpp"

namespace gvs::dsp {
namespace {

const char* const kNames[] = {"thesis", "thesis-orb", "thesis-fft", "thesis-laplacian"};

std::unique_ptr<VelocityEstimator> make(const std::string& name) {
  EstimatorConfig cfg;
  cfg.method = name;
  return make_estimator(cfg);
}

TEST(ThesisEstimators, AreRegisteredByName) {
  const auto names = estimator_names();
  for (const char* n : kNames) {
    EXPECT_NE(std::find(names.begin(), names.end(), n), names.end()) << n;
    EXPECT_NE(make(n), nullptr) << n;
  }
}

TEST(ThesisEstimators, BadFramesGiveAReasonAndQualityZero) {
  struct Bad {
    cv::Mat gray;
    Method reason;
  };
  const Bad bad[] = {{cv::Mat(), Method::empty_frame},
                     {cv::Mat(384, 512, CV_8UC3, cv::Scalar::all(100)), Method::bad_format},
                     {cv::Mat(383, 512, CV_8UC1, cv::Scalar(100)), Method::wrong_size},
                     {cv::Mat(384, 640, CV_8UC1, cv::Scalar(100)), Method::wrong_size}};
  for (const char* n : kNames) {
    const auto est = make(n);
    for (const Bad& b : bad) {
      FrameView f;
      f.gray = b.gray;
      f.index = 7;
      f.t_ns = 1000;
      VelocityEstimate e;
      EXPECT_NO_THROW(e = est->estimate(f)) << n;
      EXPECT_EQ(e.method, b.reason) << n;
      EXPECT_EQ(e.quality, 0.0) << n;
      EXPECT_EQ(e.index, 7) << n;
      EXPECT_FALSE(e.has_speed || e.has_direction) << n;
    }
  }
}

TEST(ThesisEstimators, EstimateTimeIsTheLightCentre) {
  const cv::Mat frame = test::blob_texture(512, 384, 9);
  for (const char* n : kNames) {
    const auto est = make(n);
    FrameView f;
    f.gray = frame;
    f.t_ns = 5'000'000'000;
    f.exposure.exposure_us = 1000.0;
    f.exposure.pulses[0] = {0.0, 20.0};
    f.exposure.pulses[1] = {400.0, 20.0};
    f.exposure.pulse_count = 2;
    const VelocityEstimate e = est->estimate(f);
    EXPECT_EQ(e.t_ns, 5'000'000'000 + 210'000) << n;  // (10 + 410) / 2 us
  }
}

TEST(ThesisEstimators, FirstFrameOfPairMethodsHasNoPairEstimate) {
  const cv::Mat frame = test::blob_texture(512, 384, 9);
  const auto orb = make("thesis-orb");
  FrameView f;
  f.gray = frame;
  const VelocityEstimate e = orb->estimate(f);
  EXPECT_EQ(e.method, Method::no_previous);
  EXPECT_EQ(e.quality, 0.0);
  // After reset() the next frame is a first frame again.
  orb->estimate(f);
  orb->reset();
  EXPECT_EQ(orb->estimate(f).method, Method::no_previous);
}

TEST(ThesisEstimators, SameTimeTwiceIsBadTime) {
  const cv::Mat frame = test::blob_texture(512, 384, 9);
  const auto orb = make("thesis-orb");
  FrameView f;
  f.gray = frame;
  orb->estimate(f);
  const VelocityEstimate e = orb->estimate(f);
  EXPECT_EQ(e.method, Method::bad_time);
  EXPECT_EQ(e.quality, 0.0);
}

}  // namespace
}  // namespace gvs::dsp
