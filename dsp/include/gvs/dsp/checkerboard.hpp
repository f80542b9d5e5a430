// Finding a printed checkerboard in a camera frame (gvs calibrate scale).
#pragma once

#include <optional>
#include <vector>

#include <opencv2/core/mat.hpp>

#include "gvs/dsp/calibration.hpp"

namespace gvs::dsp {

struct CheckerboardMeasurement {
  std::vector<cv::Point2f> corners;  ///< inner corners, sub-pixel, row by row
  GridScale scale;
};

/// Finds the `inner` corners (columns x rows of inner corners, e.g. 9x6 for
/// a 10x7-square board) in an 8-bit gray image with OpenCV's detector,
/// refines them to sub-pixel and measures the scale. Nullopt when the board
/// is not found (out of view, blurred, too dark).
std::optional<CheckerboardMeasurement> measure_checkerboard(const cv::Mat& gray, cv::Size inner, double square_mm);

}  // namespace gvs::dsp
