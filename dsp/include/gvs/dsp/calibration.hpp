// Fitting the sensor to a car: the ground scale (mm per pixel) from a printed
// checkerboard of known square size, and the camera's mounting yaw from a
// drive in a straight line. Pure maths on numbers the tools measured
// (corner positions, per-frame directions): `gvs calibrate` does the I/O.
#pragma once

#include <cstddef>
#include <optional>
#include <vector>

#include <opencv2/core/types.hpp>

namespace gvs::dsp {

/// What a checkerboard's inner corners say about the camera.
struct GridScale {
  double mm_per_px = 0.0;          ///< square size / mean corner spacing
  double spacing_along_rows_px = 0.0;  ///< mean distance of horizontal neighbours
  double spacing_along_cols_px = 0.0;  ///< mean distance of vertical neighbours
  double spacing_spread_pct = 0.0;     ///< std of all neighbour distances, % of their mean
  double anisotropy_pct = 0.0;     ///< (rows - cols) / mean, %: non-zero when the camera looks obliquely
  double grid_rotation_deg = 0.0;  ///< direction of the board's rows in the image, CCW from +x (image columns)
};

/// `corners`: inner corners row by row, as cv::findChessboardCorners returns
/// them (`inner.width` per row, `inner.height` rows). The scale is the
/// square size over the mean distance between neighbouring corners:
///   mm_per_px = square_mm / mean(|c[i+1] - c[i]|)
/// (a pinhole camera looking straight down images the flat ground at one
/// scale; Hartley & Zisserman, Multiple View Geometry, 2nd ed., sec. 8.1.1).
/// Returns nullopt when the corner count does not match `inner` or a
/// spacing is zero.
std::optional<GridScale> grid_scale(const std::vector<cv::Point2f>& corners, cv::Size inner, double square_mm);

/// The mounting yaw from directions measured while the car drove straight
/// ahead (truth: 0 deg). A camera turned by +delta (CCW from above) but
/// configured with `configured_yaw_deg` reports every direction off by
/// (configured - actual), so
///   mount_yaw = configured_yaw - median(direction).
/// The median ignores the odd wrong frame; the spread is the median absolute
/// deviation scaled to a standard deviation (x 1.4826, Rousseeuw & Croux 1993).
struct MountYawFit {
  double mount_yaw_deg = 0.0;    ///< the value to configure
  double median_direction_deg = 0.0;
  double spread_deg = 0.0;       ///< robust standard deviation of the directions
  std::size_t frames = 0;
};
/// Nullopt with fewer than `min_frames` directions.
std::optional<MountYawFit> fit_mount_yaw(std::vector<double> directions_deg, double configured_yaw_deg,
                                         std::size_t min_frames = 20);

}  // namespace gvs::dsp
