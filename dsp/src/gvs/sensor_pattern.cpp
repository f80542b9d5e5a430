#include "gvs/dsp/sensor_pattern.hpp"

#include <algorithm>
#include <cstdint>

namespace gvs::dsp {

SensorPattern::SensorPattern(cv::Size size)
    : columns_(static_cast<std::size_t>(size.width), 0.0f),
      column_sum_(static_cast<std::size_t>(size.width), 0.0),
      pixels_(cv::Mat::zeros(size, CV_32F)) {}

void SensorPattern::learn_columns(const cv::Mat& gray, double mean_grey) {
  std::fill(column_sum_.begin(), column_sum_.end(), 0.0);
  for (int r = 0; r < gray.rows; ++r) {
    const auto* g = gray.ptr<std::uint8_t>(r);
    for (int c = 0; c < gray.cols; ++c) column_sum_[static_cast<std::size_t>(c)] += g[c];
  }
  column_frames_ = std::min(column_frames_ + 1, 50);
  const double a = 1.0 / column_frames_;
  for (std::size_t c = 0; c < column_sum_.size(); ++c) {
    const double offset = column_sum_[c] / gray.rows - mean_grey;
    columns_[c] += static_cast<float>(a * (offset - static_cast<double>(columns_[c])));
  }
}

double SensorPattern::fine_texture_energy(const cv::Mat& gray) {
  std::int64_t sum_sq = 0;
  for (int r = 0; r + kTextureStepPx < gray.rows; ++r) {
    const auto* g = gray.ptr<std::uint8_t>(r);
    const auto* below = gray.ptr<std::uint8_t>(r + kTextureStepPx);
    for (int c = 0; c + kTextureStepPx < gray.cols; ++c) {
      const int along_row = g[c + kTextureStepPx] - g[c];
      const int along_col = below[c] - g[c];
      sum_sq += along_row * along_row + along_col * along_col;
    }
  }
  const double steps = 2.0 * (gray.rows - kTextureStepPx) * (gray.cols - kTextureStepPx);
  return steps > 0.0 ? static_cast<double>(sum_sq) / steps : 0.0;
}

void SensorPattern::learn_pixels(const cv::Mat& gray, double mean_grey) {
  pixel_frames_ = std::min(pixel_frames_ + 1, 100);
  // Inverse-variance weights, faded over 100 frames (header). The +1 grey
  // level^2 keeps a uniform frame's weight finite.
  constexpr double kKept = 1.0 - 1.0 / 100.0;
  const double weight = 1.0 / (fine_texture_energy(gray) + 1.0);
  pixel_weight_sum_ = kKept * pixel_weight_sum_ + weight;
  const auto a = static_cast<float>(weight / pixel_weight_sum_);
  const auto m = static_cast<float>(mean_grey);
  for (int r = 0; r < gray.rows; ++r) {
    const auto* g = gray.ptr<std::uint8_t>(r);
    auto* p = pixels_.ptr<float>(r);
    for (int c = 0; c < gray.cols; ++c) p[c] += a * (static_cast<float>(g[c]) - m - p[c]);
  }
}

const float* SensorPattern::columns() const {
  return column_frames_ >= kColumnMinFrames ? columns_.data() : nullptr;
}

void SensorPattern::forget() {
  column_frames_ = 0;
  pixel_frames_ = 0;
  pixel_weight_sum_ = 0.0;
  pixels_.setTo(cv::Scalar::all(0.0));
  std::fill(columns_.begin(), columns_.end(), 0.0f);
}

}  // namespace gvs::dsp
