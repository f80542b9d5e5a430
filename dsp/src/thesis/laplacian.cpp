// Speed from the Laplacian's standard deviation, thesis 5.3 and Fig. A.6.
#include <algorithm>
#include <array>
#include <cmath>

#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include "gvs/dsp/thesis_laplacian.hpp"

namespace gvs::dsp::thesis {

namespace {

// The inverse model, fitted on gvs's simulator (drivers/src/sim): scenarios
// "accel" and "const", seeds 1..2, continuous 3 ms exposure, normal light,
// 512x384 px at 0.1 mm/px, 1980 frames. Produced by
//   cmake --build build/thesis --target thesis_laplacian_fit
//   build/thesis/tests/dsp/thesis_laplacian_fit 2
// (tests/dsp/thesis_laplacian_fit.cpp), which prints this table.
// lap_std(v) = a * exp(b * v) on [speed_lo, speed_hi] m/s; the pieces meet
// at knots (median lap_std at 0, 1, 2, 5, 10, 15, 20, 40, 70, 100, 140 km/h
// and between). Checked by the same program on seed 3 (990 frames):
//   truth 0-15 km/h: RMS error 0.20 m/s, median |relative error| 6.7 %
//   15-36 km/h: 1.09 m/s, 9.8 %;  36-72 km/h: 2.60 m/s, 9.8 %;
//   72-144 km/h: 3.38 m/s, 4.1 %.
// Above about 20 m/s the curve is nearly flat (|b| < 0.007 per m/s), as
// the thesis's Fig. 5.6 shows: small changes of texture or light move the
// speed a lot there.
// BEGIN FITTED MODEL
constexpr std::array<LaplacianSegment, 16> kFittedModel{{
    {0.0000, 0.2778, 106.738316, -2.89509881},
    {0.2778, 0.5556, 62.3558873, -0.960019252},
    {0.5556, 1.0000, 46.6416619, -0.437364202},
    {1.0000, 1.3889, 43.6157826, -0.3702891},
    {1.3889, 2.0000, 31.3245919, -0.131957868},
    {2.0000, 2.7778, 32.8503096, -0.155736717},
    {2.7778, 3.5000, 26.0319222, -0.0719871782},
    {3.5000, 4.1667, 23.7827072, -0.0461686548},
    {4.1667, 5.5556, 25.3889526, -0.061853954},
    {5.5556, 7.0000, 19.7131336, -0.0163087253},
    {7.0000, 8.5000, 22.3567131, -0.0342860885},
    {8.5000, 11.1111, 20.414377, -0.0235934731},
    {11.1111, 14.0000, 18.187174, -0.0131964221},
    {14.0000, 19.4444, 17.6594514, -0.0110931728},
    {19.4444, 27.7778, 16.1448711, -0.00648163911},
    {27.7778, 38.8889, 15.1970672, -0.0043036408},
}};
// END FITTED MODEL

}  // namespace

std::span<const LaplacianSegment> fitted_laplacian_model() { return {kFittedModel.data(), kFittedModel.size()}; }

LaplacianSpeed invert_laplacian_model(double lap_std, std::span<const LaplacianSegment> model) {
  LaplacianSpeed out;
  if (model.empty() || !(lap_std > 0.0) || !std::isfinite(lap_std)) return out;
  // Direct piece: sigma = a * exp(b * v)  =>  inverse: v = ln(sigma / a) / b.
  // The switching points are the pieces' ends, sigma(speed_lo) and sigma(speed_hi).
  auto sigma_at = [](const LaplacianSegment& s, double v) { return s.a * std::exp(s.b * v); };
  // The piece whose lap_std range contains the measurement; at a switching
  // point rounded table values can leave a hair's gap, so otherwise the
  // piece nearest in ln(lap_std) is used (inside the model's overall range).
  const LaplacianSegment* best = nullptr;
  double best_gap = 1e300;
  for (const LaplacianSegment& s : model) {
    if (s.b == 0.0 || !(s.a > 0.0)) continue;
    const double s_lo = sigma_at(s, s.speed_lo_mps);
    const double s_hi = sigma_at(s, s.speed_hi_mps);
    const double top = std::max(s_lo, s_hi);
    const double bottom = std::min(s_lo, s_hi);
    const double gap = lap_std > top ? std::log(lap_std / top) : (lap_std < bottom ? std::log(bottom / lap_std) : 0.0);
    if (gap < best_gap) {
      best_gap = gap;
      best = &s;
    }
  }
  constexpr double kMaxGapLn = 0.01;  // 1 %: a rounding gap, not outside the model
  if (best != nullptr && best_gap <= kMaxGapLn) {
    out.speed_mps = std::clamp(std::log(lap_std / best->a) / best->b, best->speed_lo_mps, best->speed_hi_mps);
    // Quality: how much lap_std changes per 1 m/s here, |d ln(sigma) / dv| = |b|,
    // capped at 1. Where the curve flattens (high speed) the speed is vague.
    out.quality = std::min(1.0, std::abs(best->b));
    out.ok = true;
    return out;
  }
  // Outside the model: clamp to the nearer end (sharper than the slowest
  // piece: standing, thesis ch. 6; blurrier than the fastest: its top speed).
  const LaplacianSegment& first = model.front();
  const LaplacianSegment& last = model.back();
  const double sharpest = sigma_at(first, first.speed_lo_mps);
  out.speed_mps = lap_std >= sharpest ? first.speed_lo_mps : last.speed_hi_mps;
  out.clamped = true;
  out.quality = lap_std >= sharpest ? 0.5 : 0.05;
  out.ok = true;
  return out;
}

LaplacianBlur::LaplacianBlur(double mm_per_px, const LaplacianConfig& config) : ksize_(config.laplacian_ksize) {
  const int radius = std::max(1, static_cast<int>(std::lround(config.morph_radius_mm / mm_per_px)));
  // Cross-shaped element of size 2r+1 (thesis eq. 4.3 uses the 3x3 cross).
  element_ = cv::getStructuringElement(cv::MORPH_CROSS, cv::Size(2 * radius + 1, 2 * radius + 1),
                                       cv::Point(radius, radius));
}

double LaplacianBlur::lap_std(const cv::Mat& gray) {
  if (gray.empty() || gray.type() != CV_8UC1) return -1.0;
  // Thesis 5.3: "erosion and dilation, or closing, on the original frame"
  // (Fig. 5.4). We do the closing it names: dilate, then erode.
  cv::morphologyEx(gray, morph_, cv::MORPH_CLOSE, element_);
  // Laplacian (thesis eq. 5.3): d2f/dx2 + d2f/dy2, 3x3 aperture.
  cv::Laplacian(morph_, lap_, CV_32F, ksize_);
  cv::Scalar mean;
  cv::Scalar stddev;
  cv::meanStdDev(lap_, mean, stddev);
  return stddev[0];
}

}  // namespace gvs::dsp::thesis
