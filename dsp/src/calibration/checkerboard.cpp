#include "gvs/dsp/checkerboard.hpp"

#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

namespace gvs::dsp {

std::optional<CheckerboardMeasurement> measure_checkerboard(const cv::Mat& gray, cv::Size inner, double square_mm) {
  if (gray.empty() || gray.type() != CV_8UC1) return std::nullopt;
  CheckerboardMeasurement m;
  const int flags = cv::CALIB_CB_ADAPTIVE_THRESH | cv::CALIB_CB_NORMALIZE_IMAGE;
  if (!cv::findChessboardCorners(gray, inner, m.corners, flags)) {
    // The sector-based detector copes better with blur and uneven light.
    if (!cv::findChessboardCornersSB(gray, inner, m.corners, cv::CALIB_CB_NORMALIZE_IMAGE)) return std::nullopt;
  } else {
    cv::cornerSubPix(gray, m.corners, cv::Size(5, 5), cv::Size(-1, -1),
                     cv::TermCriteria(cv::TermCriteria::EPS + cv::TermCriteria::COUNT, 50, 0.01));
  }
  const auto scale = grid_scale(m.corners, inner, square_mm);
  if (!scale) return std::nullopt;
  m.scale = *scale;
  return m;
}

}  // namespace gvs::dsp
