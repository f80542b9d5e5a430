// The thesis's own frames (shared/testdata/thesis-frames, see its README):
// what the thesis-fft baseline and gvs read on them. True axis of the vertical_*,
// blobnoise_* and saltpepper_* frames: straight ahead, 0 deg.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>

#include "gvs/dsp/vocabulary.hpp"
#include "gvs/dsp/gvs_estimator.hpp"
#include "gvs/dsp/thesis.hpp"

namespace gvs::dsp {
namespace {

std::filesystem::path frames_dir() {
  const char* shared = std::getenv("GVS_SHARED_DIR");
  return std::filesystem::path(shared != nullptr ? shared : "../shared") / "testdata" / "thesis-frames";
}

/// Loads a thesis frame; a missing or unreadable file fails the test.
cv::Mat load(const std::string& name) {
  const std::filesystem::path p = frames_dir() / (name + ".png");
  cv::Mat g = cv::imread(p.string(), cv::IMREAD_GRAYSCALE);
  EXPECT_FALSE(g.empty()) << "thesis frame missing or unreadable: " << p
                          << " (set GVS_SHARED_DIR to the shared/ folder)";
  return g;
}

struct Reading {
  bool ok = false;
  double axis_deg = 0.0;
  double step_deg = 0.0;  ///< one row of the analysed column, in degrees
  double lap_std = 0.0;
};

Reading read_frame(const std::string& name) {
  Reading r;
  const cv::Mat g = load(name);
  if (g.empty()) return r;
  thesis::FftOrientation fft(g.cols, g.rows);
  const thesis::FftAxis a = fft.measure(g);
  thesis::LaplacianBlur lap(0.1);
  r.ok = a.ok;
  r.axis_deg = a.axis_cam_deg;
  r.step_deg = rad_to_deg(std::atan(static_cast<double>(g.cols) / (static_cast<double>(g.rows) * 75.0)));
  r.lap_std = lap.lap_std(g);
  std::printf("%-16s %4dx%-4d thesis-fft axis %6.2f deg (one row = %.2f deg), lap_std %6.2f\n", name.c_str(), g.cols,
              g.rows, r.axis_deg, r.step_deg, r.lap_std);
  return r;
}

// The thesis documents about 1 deg for the FFT method within +-20 deg. On
// its own clean vertical frames the baseline reads within one row of the
// analysed column, which at 1152x648 is 1.36 deg (so "about 1 deg" holds
// only as "one quantisation step").
TEST(ThesisFrames, FftOnCleanVerticalFramesIsWithinOneStep) {
  for (const char* n : {"vertical_mb_1", "vertical_mb_2", "vertical_mb_3"}) {
    const Reading r = read_frame(n);
    ASSERT_TRUE(r.ok) << n;
    EXPECT_LE(std::abs(r.axis_deg), r.step_deg + 1e-9) << n;
  }
}

TEST(ThesisFrames, FftOnNoisyAndUnblurredFramesIsReported) {
  // Reported, not asserted beyond "measured": vertical_mb_0 has no blur,
  // blobnoise_3 is very low contrast, photo_diagonal is a real photograph
  // whose streaks (about 33 deg above the x axis) put the axis near -57 deg
  // in camera axes, outside the one-column method's range.
  for (const char* n : {"vertical_mb_0", "blobnoise_0", "blobnoise_3", "blobnoise_6", "saltpepper_0", "saltpepper_3",
                        "photo_diagonal"}) {
    const Reading r = read_frame(n);
    EXPECT_TRUE(r.ok) << n;
    EXPECT_GT(r.axis_deg, -90.0);
    EXPECT_LE(r.axis_deg, 90.0);
  }
}

// These frames of the thesis's straight runs come out straight ahead within 1 deg.
// Their streaks are 20-100 px; the 20-30 px ones (vertical_mb_0/1,
// blobnoise_0, saltpepper_0) are too short for a speed without a previous
// frame, and their spectra's orientation is 1.0-1.5 deg off (the texture's
// own anisotropy): the axis must come from the streak end's lag.
TEST(ThesisFrames, GvsReadsEveryFrameStraightAheadWithinOneDegree) {
  for (const char* n : {"vertical_mb_0", "vertical_mb_1", "vertical_mb_2", "vertical_mb_3", "blobnoise_0",
                        "blobnoise_3", "blobnoise_6", "saltpepper_0", "saltpepper_3"}) {
    const cv::Mat g = load(n);
    ASSERT_FALSE(g.empty()) << n;
    EstimatorConfig config;
    config.camera = CameraGeometry{g.cols, g.rows, 0.1, 0.0};
    GvsEstimator gvs(config);  // a new one per frame: no previous frame, no recent speed
    FrameView frame;
    frame.gray = g;
    frame.exposure.exposure_us = 3000.0;
    const VelocityEstimate e = gvs.estimate(frame);
    std::printf("%-16s gvs direction %7.3f deg, quality %.2f, %s\n", n, e.direction_deg, e.quality, method_word(e.method));
    ASSERT_TRUE(e.has_direction) << n << ": " << e.method;
    // One frame cannot tell forwards from backwards: 0 or 180 deg.
    const double off_axis_deg = std::abs(std::remainder(e.direction_deg, 180.0));
    EXPECT_LE(off_axis_deg, 1.0) << n << ": " << e.method;
  }
}

TEST(ThesisFrames, LaplacianStdFallsAsTheThesisBlurGrows) {
  double previous = 1e9;
  for (const char* n : {"vertical_mb_0", "vertical_mb_1", "vertical_mb_2", "vertical_mb_3"}) {
    const Reading r = read_frame(n);
    ASSERT_TRUE(r.ok) << n;
    EXPECT_LT(r.lap_std, previous) << n;
    previous = r.lap_std;
  }
}

}  // namespace
}  // namespace gvs::dsp
