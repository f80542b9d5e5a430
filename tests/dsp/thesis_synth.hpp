// Synthetic ground textures for the thesis-baseline tests: random blobs,
// shifted by a known sub-pixel amount or smeared by a line kernel.
#pragma once

#include <cmath>
#include <cstdint>

#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

namespace gvs::dsp::test {

/// Grey blobs of random size and brightness on a mid-grey background,
/// slightly smoothed so that sub-pixel shifts are meaningful.
inline cv::Mat blob_texture(int width, int height, std::uint64_t seed, int blobs_per_kpx = 6) {
  cv::RNG rng(seed);
  cv::Mat img(height, width, CV_8UC1, cv::Scalar(110));
  const int count = width * height / 1000 * blobs_per_kpx;
  for (int i = 0; i < count; ++i) {
    const cv::Point c(rng.uniform(0, width), rng.uniform(0, height));
    const cv::Size axes(rng.uniform(1, 6), rng.uniform(1, 6));
    cv::ellipse(img, c, axes, rng.uniform(0.0, 180.0), 0.0, 360.0, cv::Scalar(rng.uniform(20, 235)), cv::FILLED,
                cv::LINE_AA);
  }
  cv::GaussianBlur(img, img, cv::Size(0, 0), 0.8);
  return img;
}

/// The centre width x height of `texture` after moving its content by
/// (d_row, d_col) pixels (sub-pixel, bilinear).
inline cv::Mat shifted_crop(const cv::Mat& texture, double d_row, double d_col, int width, int height) {
  const cv::Mat m = (cv::Mat_<double>(2, 3) << 1.0, 0.0, d_col, 0.0, 1.0, d_row);
  cv::Mat moved;
  cv::warpAffine(texture, moved, m, texture.size(), cv::INTER_LINEAR, cv::BORDER_REFLECT);
  const cv::Rect r((texture.cols - width) / 2, (texture.rows - height) / 2, width, height);
  return moved(r).clone();
}

/// Motion blur: `texture` convolved with a line of `length_px` along the
/// texture motion at `axis_cam_deg` in camera axes (x = rows towards the rear,
/// y = columns to the right), then the centre width x height.
inline cv::Mat line_blurred_crop(const cv::Mat& texture, double axis_cam_deg, double length_px, int width,
                                 int height) {
  const int half = static_cast<int>(std::ceil(length_px / 2.0)) + 2;
  cv::Mat k8 = cv::Mat::zeros(2 * half + 1, 2 * half + 1, CV_8UC1);
  const double a = axis_cam_deg * CV_PI / 180.0;
  const double dr = std::cos(a) * length_px / 2.0;  // rows
  const double dc = std::sin(a) * length_px / 2.0;  // columns
  constexpr int kShift = 4;                          // sub-pixel end points
  const double scale = 1 << kShift;
  cv::line(k8, cv::Point(static_cast<int>(std::lround((half - dc) * scale)), static_cast<int>(std::lround((half - dr) * scale))),
           cv::Point(static_cast<int>(std::lround((half + dc) * scale)), static_cast<int>(std::lround((half + dr) * scale))),
           cv::Scalar(255), 1, cv::LINE_AA, kShift);
  cv::Mat kernel;
  k8.convertTo(kernel, CV_32F);
  kernel /= cv::sum(kernel)[0];
  cv::Mat blurred;
  cv::filter2D(texture, blurred, -1, kernel, cv::Point(-1, -1), 0.0, cv::BORDER_REFLECT);
  const cv::Rect r((texture.cols - width) / 2, (texture.rows - height) / 2, width, height);
  return blurred(r).clone();
}

}  // namespace gvs::dsp::test
