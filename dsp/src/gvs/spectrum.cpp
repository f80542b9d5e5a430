// Windowed spectrum (see spectrum.hpp).
#include "gvs/dsp/spectrum.hpp"

#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include "gvs/dsp/geometry.hpp"

namespace gvs::dsp {

WindowedSpectrum::WindowedSpectrum(cv::Size size) : size_(size) {
  cv::createHanningWindow(window_, size, CV_32F);
  work_.create(size, CV_32F);
  window_sum_ = cv::sum(window_)[0];
}

void WindowedSpectrum::compute(const cv::Mat& gray, cv::Mat& spectrum, const float* column_offsets) {
  // m = sum(g w) / sum(w): the windowed mean, so that f has no DC term.
  double weighted = 0.0;
  for (int r = 0; r < size_.height; ++r) {
    const auto* g = gray.ptr<unsigned char>(r);
    const float* w = window_.ptr<float>(r);
    for (int c = 0; c < size_.width; ++c) weighted += static_cast<double>(g[c] * w[c]);
  }
  const auto m = static_cast<float>(weighted / window_sum_);
  for (int r = 0; r < size_.height; ++r) {
    const auto* g = gray.ptr<unsigned char>(r);
    const float* w = window_.ptr<float>(r);
    float* f = work_.ptr<float>(r);
    if (column_offsets != nullptr) {
      for (int c = 0; c < size_.width; ++c) f[c] = (static_cast<float>(g[c]) - column_offsets[c] - m) * w[c];
    } else {
      for (int c = 0; c < size_.width; ++c) f[c] = (static_cast<float>(g[c]) - m) * w[c];
    }
  }
  dft_.run(work_, spectrum);
}

std::vector<double> angular_frequencies(int n) {
  std::vector<double> k(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) {
    const int j = i < (n + 1) / 2 ? i : i - n;
    k[static_cast<std::size_t>(i)] = 2.0 * kPi * j / n;
  }
  return k;
}

}  // namespace gvs::dsp
