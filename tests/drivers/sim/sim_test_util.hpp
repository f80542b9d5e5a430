// Helpers for the simulator tests: controlled-motion simulators and image
// measurements (shift by phase correlation, blur length by the derivative
// autocorrelation).
#pragma once

#include <cmath>
#include <utility>

#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include "gvs/drivers/simulator.hpp"

namespace gvs::drivers::sim::test {

/// A config whose sensor has no fixed pattern and no light falloff (both are
/// static in the image and would pull phase correlation towards zero shift).
inline SimulatorConfig geometry_config(std::uint64_t seed = 3) {
  SimulatorConfig c;
  c.seed = seed;
  c.sensor.fixed_pattern_noise = false;
  c.sensor.light_falloff = false;
  return c;
}

/// A config with a noise-free sensor (no temporal noise, no fixed pattern).
inline SimulatorConfig clean_config(std::uint64_t seed = 3) {
  SimulatorConfig c = geometry_config(seed);
  c.sensor.shot_and_read_noise = false;
  return c;
}

inline core::ExposurePlan strobe(double start_us, double duration_us, double exposure_us = 3000.0) {
  core::ExposurePlan p;
  p.exposure_us = exposure_us;
  p.pulse_count = 1;
  p.pulses[0] = {start_us, duration_us};
  return p;
}

inline core::ExposurePlan continuous(double exposure_us) {
  core::ExposurePlan p;
  p.exposure_us = exposure_us;
  return p;
}

inline cv::Mat render(Simulator& sim, std::int64_t index, const core::ExposurePlan& plan) {
  SimFrame f;
  sim.render(index, plan, f);
  return f.gray.clone();
}

struct Shift {
  double d_row = 0.0;  ///< texture moved this many rows down from a to b
  double d_col = 0.0;  ///< ... and this many columns right
  double response = 0.0;
};

/// How far the texture moved from `a` to `b` (sub-pixel phase correlation
/// with a Hann window).
inline Shift measure_shift(const cv::Mat& a, const cv::Mat& b) {
  cv::Mat fa, fb, window;
  a.convertTo(fa, CV_64F);
  b.convertTo(fb, CV_64F);
  cv::createHanningWindow(window, fa.size(), CV_64F);
  double response = 0.0;
  const cv::Point2d p = cv::phaseCorrelate(fa, fb, window, &response);
  return {p.y, p.x, response};
}

/// Blur length (px) along rows (`along_rows`) or columns: the lag of the most
/// negative autocorrelation of the image derivative in that direction. For a
/// box blur of length L, dI/dr = (T(r) - T(r - L)) / L, whose autocorrelation
/// has a negative peak of -Var(T) / L^2 at lag L. Searches [min_lag, max_lag].
inline double blur_length(const cv::Mat& gray, bool along_rows, int min_lag, int max_lag) {
  cv::Mat f;
  gray.convertTo(f, CV_64F);
  if (!along_rows) f = f.t();
  cv::Mat d = f.rowRange(1, f.rows) - f.rowRange(0, f.rows - 1);
  std::vector<double> c(static_cast<std::size_t>(max_lag + 2), 0.0);
  for (int lag = min_lag - 1; lag <= max_lag + 1; ++lag) {
    const cv::Mat x = d.rowRange(0, d.rows - lag);
    const cv::Mat y = d.rowRange(lag, d.rows);
    c[static_cast<std::size_t>(lag)] = x.dot(y) / static_cast<double>(x.total());
  }
  int best = min_lag;
  for (int lag = min_lag; lag <= max_lag; ++lag)
    if (c[static_cast<std::size_t>(lag)] < c[static_cast<std::size_t>(best)]) best = lag;
  // Parabolic refinement.
  const double cm = c[static_cast<std::size_t>(best - 1)];
  const double c0 = c[static_cast<std::size_t>(best)];
  const double cp = c[static_cast<std::size_t>(best + 1)];
  const double den = cm - 2.0 * c0 + cp;
  return best + (std::abs(den) > 0.0 ? 0.5 * (cm - cp) / den : 0.0);
}

/// Where (rows) the texture of `sharp` sits in `blurred`: the peak of the
/// normalised cross-correlation of a central crop of `sharp`, searched over
/// +-max_shift rows (parabolic sub-pixel refinement). For a blurred frame this
/// is the centroid of the blur (the texture autocorrelation is symmetric).
inline double row_offset(const cv::Mat& sharp, const cv::Mat& blurred, int max_shift) {
  const cv::Rect crop(64, max_shift + 8, sharp.cols - 128, sharp.rows - 2 * max_shift - 16);
  const cv::Rect search(64, 8, sharp.cols - 128, sharp.rows - 16);
  cv::Mat score;
  cv::matchTemplate(blurred(search), sharp(crop), score, cv::TM_CCOEFF_NORMED);
  cv::Point best;
  cv::minMaxLoc(score, nullptr, nullptr, nullptr, &best);
  double frac = 0.0;
  if (best.y > 0 && best.y < score.rows - 1) {
    const double cm = score.at<float>(best.y - 1, best.x);
    const double c0 = score.at<float>(best.y, best.x);
    const double cp = score.at<float>(best.y + 1, best.x);
    frac = 0.5 * (cm - cp) / (cm - 2.0 * c0 + cp);
  }
  return best.y + frac - max_shift;
}

/// Normalised autocorrelation of the row derivative at a lag (rows).
inline double derivative_autocorrelation(const cv::Mat& gray, int lag) {
  cv::Mat f;
  gray.convertTo(f, CV_64F);
  cv::Mat d = f.rowRange(1, f.rows) - f.rowRange(0, f.rows - 1);
  d -= cv::mean(d)[0];
  const cv::Mat x = d.rowRange(0, d.rows - lag);
  const cv::Mat y = d.rowRange(lag, d.rows);
  return x.dot(y) / std::sqrt(x.dot(x) * y.dot(y));
}

}  // namespace gvs::drivers::sim::test
