#include "gvs/dsp/calibration.hpp"

#include <algorithm>
#include <cmath>

#include "gvs/dsp/vocabulary.hpp"

namespace gvs::dsp {

namespace {

double median_of(std::vector<double> v) {
  const std::size_t mid = v.size() / 2;
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(mid), v.end());
  double m = v[mid];
  if (v.size() % 2 == 0) {
    m = (m + *std::max_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(mid))) / 2.0;
  }
  return m;
}

double distance(cv::Point2f a, cv::Point2f b) {
  return std::hypot(static_cast<double>(a.x) - static_cast<double>(b.x), static_cast<double>(a.y) - static_cast<double>(b.y));
}

}  // namespace

std::optional<GridScale> grid_scale(const std::vector<cv::Point2f>& corners, cv::Size inner, double square_mm) {
  if (inner.width < 2 || inner.height < 2 || !(square_mm > 0.0) ||
      corners.size() != static_cast<std::size_t>(inner.width) * static_cast<std::size_t>(inner.height)) {
    return std::nullopt;
  }
  const auto at = [&](int row, int col) { return corners[static_cast<std::size_t>(row * inner.width + col)]; };
  std::vector<double> along_rows;
  std::vector<double> along_cols;
  double row_dx = 0.0;
  double row_dy = 0.0;
  for (int r = 0; r < inner.height; ++r) {
    for (int c = 0; c < inner.width; ++c) {
      if (c + 1 < inner.width) {
        along_rows.push_back(distance(at(r, c), at(r, c + 1)));
        row_dx += static_cast<double>(at(r, c + 1).x) - static_cast<double>(at(r, c).x);
        row_dy += static_cast<double>(at(r, c + 1).y) - static_cast<double>(at(r, c).y);
      }
      if (r + 1 < inner.height) along_cols.push_back(distance(at(r, c), at(r + 1, c)));
    }
  }
  const auto mean = [](const std::vector<double>& v) {
    double s = 0.0;
    for (double x : v) s += x;
    return s / static_cast<double>(v.size());
  };
  GridScale g;
  g.spacing_along_rows_px = mean(along_rows);
  g.spacing_along_cols_px = mean(along_cols);
  std::vector<double> all = along_rows;
  all.insert(all.end(), along_cols.begin(), along_cols.end());
  const double spacing = mean(all);
  if (!(spacing > 0.0)) return std::nullopt;
  double var = 0.0;
  for (double x : all) var += (x - spacing) * (x - spacing);
  g.spacing_spread_pct = 100.0 * std::sqrt(var / static_cast<double>(all.size())) / spacing;
  g.anisotropy_pct = 100.0 * (g.spacing_along_rows_px - g.spacing_along_cols_px) / spacing;
  g.mm_per_px = square_mm / spacing;
  // Image y points down; report the angle as seen on screen (CCW positive).
  g.grid_rotation_deg = rad_to_deg(std::atan2(-row_dy, row_dx));
  return g;
}

std::optional<MountYawFit> fit_mount_yaw(std::vector<double> directions_deg, double configured_yaw_deg,
                                         std::size_t min_frames) {
  directions_deg.erase(std::remove_if(directions_deg.begin(), directions_deg.end(),
                                      [](double d) { return !std::isfinite(d); }),
                       directions_deg.end());
  if (directions_deg.size() < std::max<std::size_t>(min_frames, 1)) return std::nullopt;
  MountYawFit fit;
  fit.frames = directions_deg.size();
  fit.median_direction_deg = median_of(directions_deg);
  std::vector<double> deviation;
  deviation.reserve(directions_deg.size());
  for (double d : directions_deg) deviation.push_back(std::abs(wrap_deg(d - fit.median_direction_deg)));
  fit.spread_deg = 1.4826 * median_of(deviation);
  fit.mount_yaw_deg = wrap_deg(configured_yaw_deg - fit.median_direction_deg);
  return fit;
}

}  // namespace gvs::dsp
