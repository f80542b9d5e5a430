// gvs calibrate's parts: the scale from a checkerboard (maths and OpenCV's
// detector on a drawn board), the mounting yaw fit, and writing the values
// into a configuration without disturbing the rest of the file.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <vector>

#include <unistd.h>

#include <opencv2/imgproc.hpp>

#include "gvs/daemon/config.hpp"
#include "gvs/daemon/config_edit.hpp"
#include "gvs/dsp/checkerboard.hpp"
#include "gvs/dsp/calibration.hpp"

namespace gvs {
namespace {

std::vector<cv::Point2f> grid(cv::Size inner, double spacing_px, double rotation_deg, cv::Point2d origin) {
  const double a = rotation_deg * M_PI / 180.0;
  std::vector<cv::Point2f> c;
  for (int r = 0; r < inner.height; ++r) {
    for (int k = 0; k < inner.width; ++k) {
      // Rotation CCW on screen: image y points down.
      const double x = k * spacing_px;
      const double y = r * spacing_px;
      c.emplace_back(static_cast<float>(origin.x + x * std::cos(a) + y * std::sin(a)),
                     static_cast<float>(origin.y - x * std::sin(a) + y * std::cos(a)));
    }
  }
  return c;
}

TEST(GridScale, ExactGridGivesSquareOverSpacing) {
  const auto g = dsp::grid_scale(grid({9, 6}, 40.0, 30.0, {100, 300}), {9, 6}, 5.0);
  ASSERT_TRUE(g);
  EXPECT_NEAR(g->mm_per_px, 5.0 / 40.0, 1e-6);
  EXPECT_NEAR(g->grid_rotation_deg, 30.0, 1e-3);
  EXPECT_NEAR(g->anisotropy_pct, 0.0, 1e-3);
  EXPECT_NEAR(g->spacing_spread_pct, 0.0, 1e-3);
}

TEST(GridScale, StretchedGridShowsAnisotropy) {
  auto c = grid({9, 6}, 40.0, 0.0, {50, 50});
  for (auto& p : c) p.y = 50.0F + (p.y - 50.0F) * 1.1F;  // columns 10 % longer: oblique view
  const auto g = dsp::grid_scale(c, {9, 6}, 5.0);
  ASSERT_TRUE(g);
  EXPECT_LT(g->anisotropy_pct, -5.0);
}

TEST(GridScale, WrongCornerCountOrSizeIsRefused) {
  EXPECT_FALSE(dsp::grid_scale(grid({9, 6}, 40.0, 0.0, {0, 0}), {8, 6}, 5.0));
  EXPECT_FALSE(dsp::grid_scale(grid({9, 6}, 40.0, 0.0, {0, 0}), {9, 6}, 0.0));
}

TEST(Checkerboard, DetectorMeasuresADrawnRotatedBlurredBoard) {
  // A 10x7-square board, 36 px squares, rotated 7 deg, blurred and noisy.
  constexpr int kSquarePx = 36;
  cv::Mat board(7 * kSquarePx + 80, 10 * kSquarePx + 80, CV_8UC1, cv::Scalar(235));
  for (int r = 0; r < 7; ++r) {
    for (int c = 0; c < 10; ++c) {
      if ((r + c) % 2 == 0) {
        cv::rectangle(board, cv::Rect(40 + c * kSquarePx, 40 + r * kSquarePx, kSquarePx, kSquarePx),
                      cv::Scalar(25), cv::FILLED);
      }
    }
  }
  cv::Mat frame;
  const cv::Mat rot = cv::getRotationMatrix2D(cv::Point2f(static_cast<float>(board.cols) / 2.0F, static_cast<float>(board.rows) / 2.0F), 7.0, 1.0);
  cv::warpAffine(board, frame, rot, cv::Size(512, 384), cv::INTER_LINEAR, cv::BORDER_CONSTANT, cv::Scalar(235));
  cv::GaussianBlur(frame, frame, cv::Size(5, 5), 1.2);
  cv::Mat noise(frame.size(), CV_8UC1);
  cv::randn(noise, 0, 4);
  cv::add(frame, noise, frame);

  const auto m = dsp::measure_checkerboard(frame, {9, 6}, 10.0);
  ASSERT_TRUE(m) << "board not found";
  EXPECT_NEAR(m->scale.mm_per_px, 10.0 / kSquarePx, 0.005 * 10.0 / kSquarePx) << "within 0.5 %";
  EXPECT_NEAR(std::abs(m->scale.grid_rotation_deg), 7.0, 0.3);
  EXPECT_LT(std::abs(m->scale.anisotropy_pct), 0.5);

  const cv::Mat blank(384, 512, CV_8UC1, cv::Scalar(128));
  EXPECT_FALSE(dsp::measure_checkerboard(blank, {9, 6}, 10.0));
}

TEST(MountYaw, MedianOfStraightDrivingGivesTheYawDespiteOutliers) {
  std::mt19937 rng(5);
  std::normal_distribution<double> noise(0.0, 0.2);
  std::vector<double> d;
  // Camera turned +2.5 deg, configured 0: every direction reads -2.5.
  for (int i = 0; i < 200; ++i) d.push_back(-2.5 + noise(rng));
  for (int i = 0; i < 15; ++i) d.push_back(170.0);  // wrong-sign frames
  d.push_back(std::nan(""));
  const auto fit = dsp::fit_mount_yaw(d, 0.0);
  ASSERT_TRUE(fit);
  // 7 % one-sided outliers move the median by ~0.02 deg, sampling by ~0.02.
  EXPECT_NEAR(fit->mount_yaw_deg, 2.5, 0.1);
  EXPECT_NEAR(fit->spread_deg, 0.2, 0.06);
  EXPECT_EQ(fit->frames, 215u);
  // Already configured at 1.0 deg: the reading is then -1.5.
  for (double& x : d) x += 1.0;
  EXPECT_NEAR(dsp::fit_mount_yaw(d, 1.0)->mount_yaw_deg, 2.5, 0.1);
  EXPECT_FALSE(dsp::fit_mount_yaw({1.0, 2.0}, 0.0)) << "too few frames";
}

TEST(ConfigEdit, ReplacesKeepsCommentsAddsAndAppends) {
  const std::string text =
      "# my car\n[source]\nuri = \"sim:sine\"\n\n[camera]\nwidth_px = 512  # sensor\nmm_per_px = 0.1   # old\n"
      "\n[log]\nlevel = \"info\"\n";
  const std::string out =
      daemon::set_config_numbers(text, "camera", {{"mm_per_px", 0.0987}, {"mount_yaw_deg", -1.25}}, "t.toml");
  EXPECT_NE(out.find("# my car"), std::string::npos);
  EXPECT_NE(out.find("mm_per_px = 0.0987  # old"), std::string::npos) << out;
  EXPECT_NE(out.find("width_px = 512  # sensor"), std::string::npos) << out;
  const daemon::DaemonConfig c = daemon::parse_config(out, "t.toml");
  EXPECT_DOUBLE_EQ(c.camera.mm_per_px, 0.0987);
  EXPECT_DOUBLE_EQ(c.camera.mount_yaw_deg, -1.25);
  EXPECT_EQ(c.log_level, "info");
  EXPECT_LT(out.find("mount_yaw_deg"), out.find("[log]")) << "added inside [camera]";

  const std::string appended = daemon::set_config_numbers("[log]\nlevel = \"warn\"\n", "camera", {{"mm_per_px", 0.2}}, "u");
  EXPECT_DOUBLE_EQ(daemon::parse_config(appended, "u").camera.mm_per_px, 0.2);
  EXPECT_EQ(daemon::parse_config(appended, "u").log_level, "warn");
}

TEST(ConfigEdit, OutOfRangeValueIsRefusedAndTheFileKept) {
  const auto file = std::filesystem::temp_directory_path() / ("gvs_cfg_edit_" + std::to_string(::getpid()) + ".toml");
  { std::ofstream(file) << "[camera]\nmm_per_px = 0.1\n"; }
  EXPECT_THROW(daemon::set_config_numbers_in_file(file, "camera", {{"mm_per_px", 0.0}}), daemon::ConfigError);
  EXPECT_DOUBLE_EQ(daemon::load_config_file(file).camera.mm_per_px, 0.1);
  daemon::set_config_numbers_in_file(file, "camera", {{"mm_per_px", 0.125}});
  EXPECT_DOUBLE_EQ(daemon::load_config_file(file).camera.mm_per_px, 0.125);
  std::filesystem::remove(file);
}

}  // namespace
}  // namespace gvs
