// Blur axis from the FFT magnitude, thesis 4.5 and Fig. A.5.
#include <algorithm>
#include <cmath>

#include <opencv2/core.hpp>

#include "gvs/dsp/vocabulary.hpp"
#include "gvs/dsp/thesis_fft.hpp"

namespace gvs::dsp::thesis {

void fft_shift(cv::Mat& m) {
  const int cx = m.cols / 2;
  const int cy = m.rows / 2;
  cv::Mat q0(m, cv::Rect(0, 0, cx, cy));
  cv::Mat q1(m, cv::Rect(cx, 0, cx, cy));
  cv::Mat q2(m, cv::Rect(0, cy, cx, cy));
  cv::Mat q3(m, cv::Rect(cx, cy, cx, cy));
  // Swap quadrants element by element: no temporary image.
  for (int r = 0; r < cy; ++r) {
    std::swap_ranges(q0.ptr<float>(r), q0.ptr<float>(r) + cx * m.channels(), q3.ptr<float>(r));
    std::swap_ranges(q1.ptr<float>(r), q1.ptr<float>(r) + cx * m.channels(), q2.ptr<float>(r));
  }
}

namespace {
constexpr double kMinContrastGrey = 1.0;  ///< grey-level standard deviation below which there is no texture

int even_dft_size(int n) {
  int s = cv::getOptimalDFTSize(n);
  while (s % 2 != 0) s = cv::getOptimalDFTSize(s + 1);
  return s;
}
}  // namespace

FftOrientation::FftOrientation(int width_px, int height_px, const FftConfig& config)
    : config_(config), width_(width_px), height_(height_px) {
  dft_width_ = even_dft_size(width_px);
  dft_height_ = even_dft_size(height_px);
  padded_ = cv::Mat::zeros(dft_height_, dft_width_, CV_32F);
  spectrum_.create(dft_height_, dft_width_, CV_32FC2);
  planes_[0].create(dft_height_, dft_width_, CV_32F);
  planes_[1].create(dft_height_, dft_width_, CV_32F);
  magnitude_.create(dft_height_, dft_width_, CV_32F);
  mag_spectrum_.create(dft_height_, dft_width_, CV_32FC2);
  filtered_.create(dft_height_, dft_width_, CV_32F);
  // Thesis 4.5 filters the magnitude image itself (Fig. A.5 applies both
  // filters to magI), with the cut-offs of Figs. 4.23 and 4.25 read as DFT
  // bins of that image:
  //   high pass, eq. 4.22: 1 + alpha (1 - h_LP), cut-off 0.5: it boosts all
  //     but the zero bin; for the arg-max below that equals removing the
  //     mean, so we simply zero the bins with |k| <= high_pass_radius;
  //   low pass, eq. 4.23: h_LP = 1 if ||k||_inf < D, D = 15 (a square).
  // Both are linear, so one mask does both. The low pass smooths the
  // spectrum's speckle so that its bright line through the centre stands out.
  band_.create(dft_height_, dft_width_, CV_32F);
  for (int r = 0; r < dft_height_; ++r) {
    auto* row = band_.ptr<float>(r);
    for (int c = 0; c < dft_width_; ++c) {
      const double u = std::abs(static_cast<double>(r - dft_height_ / 2));
      const double v = std::abs(static_cast<double>(c - dft_width_ / 2));
      const bool low_pass = std::max(u, v) < config_.low_pass_radius;
      const bool high_pass = std::hypot(u, v) > config_.high_pass_radius;
      row[c] = (low_pass && high_pass) ? 1.0F : 0.0F;
    }
  }
  fft_shift(band_);  // the mask is applied to an unshifted DFT
}

FftAxis FftOrientation::measure(const cv::Mat& gray) {
  FftAxis out;
  if (gray.empty() || gray.type() != CV_8UC1 || gray.cols != width_ || gray.rows != height_) return out;
  cv::Scalar mean_grey;
  cv::Scalar std_grey;
  cv::meanStdDev(gray, mean_grey, std_grey);
  if (std_grey[0] < kMinContrastGrey) return out;  // a flat frame has no blur to read

  // 1. Magnitude spectrum of the frame, log scaled and shifted (thesis 4.5,
  //    Fig. 4.21): M = log(1 + |DFT(f)|), zero frequency at the centre.
  gray.convertTo(padded_(cv::Rect(0, 0, width_, height_)), CV_32F);
  cv::dft(padded_, spectrum_, cv::DFT_COMPLEX_OUTPUT);
  cv::split(spectrum_, planes_);
  cv::magnitude(planes_[0], planes_[1], magnitude_);
  magnitude_ += cv::Scalar::all(1.0);
  cv::log(magnitude_, magnitude_);
  fft_shift(magnitude_);

  // 2. Thesis high/low pass on the magnitude image (Fig. A.5, eqs. 4.22, 4.23).
  cv::dft(magnitude_, mag_spectrum_, cv::DFT_COMPLEX_OUTPUT);
  cv::split(mag_spectrum_, planes_);
  cv::multiply(planes_[0], band_, planes_[0]);
  cv::multiply(planes_[1], band_, planes_[1]);
  cv::merge(planes_, 2, mag_spectrum_);
  cv::idft(mag_spectrum_, filtered_, cv::DFT_REAL_OUTPUT | cv::DFT_SCALE);

  // 3. The column column_offset_px right of the centre, inside the circle of
  //    radius mask_radius_px (Fig. A.5): the row of maximum magnitude.
  const int cx = dft_width_ / 2;
  const int cy = dft_height_ / 2;
  const int col = cx + config_.column_offset_px;
  const int r2 = config_.mask_radius_px * config_.mask_radius_px - config_.column_offset_px * config_.column_offset_px;
  if (col >= dft_width_ || r2 < 0) return out;
  const int half = std::min({static_cast<int>(std::sqrt(static_cast<double>(r2))), cy, dft_height_ - 1 - cy});
  float best = -1e30F;
  float worst = 1e30F;
  double sum = 0.0;
  int best_dr = 0;
  for (int dr = -half; dr <= half; ++dr) {
    const float v = filtered_.at<float>(cy + dr, col);
    sum += static_cast<double>(v);
    worst = std::min(worst, v);
    if (v > best) {
      best = v;
      best_dr = dr;
    }
  }
  const double span = static_cast<double>(best) - static_cast<double>(worst);
  if (!(span > 1e-6)) return out;  // flat column: no texture, nothing measured

  // 4. The line from the centre to (col offset, best_dr) is perpendicular to
  //    the blur (thesis 4.5, Fig. 4.26). In physical frequency (cycles/px)
  //    that line is f = (f_row, f_col) = (dr / H, dc / W): bins are 1/H apart
  //    along rows and 1/W along columns (the thesis took bins as equal; they
  //    are not for a non-square frame). The blur axis b is perpendicular:
  //    b = (b_row, b_col) = (dc / W, -dr / H). In camera axes x = rows,
  //    y = columns, so axis_cam = atan2(-dr / H, dc / W).
  const double dc = static_cast<double>(config_.column_offset_px);
  const double dr = static_cast<double>(best_dr);
  out.axis_cam_deg = wrap_axis_deg(rad_to_deg(
      std::atan2(-dr / static_cast<double>(dft_height_), dc / static_cast<double>(dft_width_))));
  out.peak_row_offset = best_dr;
  // Prominence of the peak over the column's mean, relative to its range.
  const double mean = sum / static_cast<double>(2 * half + 1);
  out.quality = std::clamp((static_cast<double>(best) - mean) / span, 0.0, 1.0);
  out.ok = true;
  return out;
}

}  // namespace gvs::dsp::thesis
