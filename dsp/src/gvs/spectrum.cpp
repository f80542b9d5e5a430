// Windowed spectrum (see spectrum.hpp).
#include "gvs/dsp/spectrum.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <opencv2/core.hpp>

#include "gvs/dsp/vocabulary.hpp"

namespace gvs::dsp {

std::vector<double> tukey_window(int n, double taper_fraction) {
  std::vector<double> w(static_cast<std::size_t>(n), 1.0);
  if (n < 2 || taper_fraction <= 0.0) return w;
  const double a = std::min(taper_fraction, 1.0);
  for (int i = 0; i < n; ++i) {
    // Distance to the nearer border, as a fraction of the frame (0 .. 0.5).
    const double edge = static_cast<double>(std::min(i, n - 1 - i)) / (n - 1);
    if (edge < a / 2.0) w[static_cast<std::size_t>(i)] = 0.5 * (1.0 - std::cos(2.0 * kPi * edge / a));
  }
  return w;
}

cv::Mat spectrum_window(cv::Size size, int type, double taper_fraction) {
  const std::vector<double> rows = tukey_window(size.height, taper_fraction);
  const std::vector<double> cols = tukey_window(size.width, taper_fraction);
  cv::Mat w(size, CV_64F);
  for (int r = 0; r < size.height; ++r) {
    for (int c = 0; c < size.width; ++c) {
      w.at<double>(r, c) = rows[static_cast<std::size_t>(r)] * cols[static_cast<std::size_t>(c)];
    }
  }
  cv::Mat out;
  w.convertTo(out, type);
  return out;
}

WindowedSpectrum::WindowedSpectrum(cv::Size size, double taper_fraction, DftPlan::Direction transform)
    : size_(size), dft_(transform, size) {
  if (transform == DftPlan::Direction::inverse_complex_to_real) {
    throw std::invalid_argument("WindowedSpectrum: the transform must be a forward one");
  }
  window_ = spectrum_window(size, CV_32F, taper_fraction);
  work_.create(size, CV_32F);
  window_sum_ = cv::sum(window_)[0];
  window_energy_ = window_.dot(window_);
}

template <class RowOffsets>
void WindowedSpectrum::compute_with(const cv::Mat& gray, cv::Mat& spectrum, RowOffsets row_offsets) {
  // m = sum((g - o) w) / sum(w): the windowed mean, so that f has no DC term.
  // Four sums side by side (one would wait on each add); m is rounded to
  // float, far coarser than the order of the adds can change it.
  double weighted[4] = {0.0, 0.0, 0.0, 0.0};
  for (int r = 0; r < size_.height; ++r) {
    const auto* g = gray.ptr<unsigned char>(r);
    const float* o = row_offsets(r);
    const float* w = window_.ptr<float>(r);
    const auto term = [&](int c) {
      const float v = o != nullptr ? static_cast<float>(g[c]) - o[c] : static_cast<float>(g[c]);
      return static_cast<double>(v * w[c]);
    };
    int c = 0;
    for (; c + 4 <= size_.width; c += 4) {
      for (int j = 0; j < 4; ++j) weighted[j] += term(c + j);
    }
    for (; c < size_.width; ++c) weighted[0] += term(c);
  }
  const auto m = static_cast<float>(((weighted[0] + weighted[1]) + (weighted[2] + weighted[3])) / window_sum_);
  for (int r = 0; r < size_.height; ++r) {
    const auto* g = gray.ptr<unsigned char>(r);
    const float* o = row_offsets(r);
    const float* w = window_.ptr<float>(r);
    float* f = work_.ptr<float>(r);
    if (o != nullptr) {
      for (int c = 0; c < size_.width; ++c) f[c] = (static_cast<float>(g[c]) - o[c] - m) * w[c];
    } else {
      for (int c = 0; c < size_.width; ++c) f[c] = (static_cast<float>(g[c]) - m) * w[c];
    }
  }
  dft_.run(work_, spectrum);
}

void WindowedSpectrum::compute(const cv::Mat& gray, cv::Mat& spectrum, const float* column_offsets) {
  // The same offsets for every row.
  compute_with(gray, spectrum, [column_offsets](int) { return column_offsets; });
}

void WindowedSpectrum::compute(const cv::Mat& gray, cv::Mat& spectrum, const cv::Mat& pixel_offsets) {
  compute_with(gray, spectrum, [&pixel_offsets](int r) { return pixel_offsets.ptr<float>(r); });
}

namespace {
// O(t) for t = 0 .. n-1 of one axis' window profile.
std::vector<double> overlap_of(const std::vector<double>& w) {
  const std::size_t n = w.size();
  double o0 = 0.0;
  for (const double v : w) o0 += v * v;
  if (o0 <= 0.0) o0 = 1.0;
  std::vector<double> o;
  o.reserve(n);
  for (std::size_t t = 0; t < n; ++t) {
    double sum = 0.0;
    for (std::size_t x = 0; x + t < n; ++x) sum += w[x] * w[x + t];
    o.push_back(sum / o0);
  }
  return o;
}
}  // namespace

WindowOverlap::WindowOverlap(cv::Size size) {
  // The same (separable) window as WindowedSpectrum, axis by axis.
  rows_ = overlap_of(tukey_window(size.height, kWindowTaper));
  cols_ = overlap_of(tukey_window(size.width, kWindowTaper));
}

double WindowOverlap::at(int dr, int dc) const {
  const int rows = static_cast<int>(rows_.size());
  const int cols = static_cast<int>(cols_.size());
  int r = ((dr % rows) + rows) % rows;
  int c = ((dc % cols) + cols) % cols;
  r = std::min(r, rows - r);  // lag -t wraps to n - t: the same overlap as +t
  c = std::min(c, cols - c);
  return rows_[static_cast<std::size_t>(r)] * cols_[static_cast<std::size_t>(c)];
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
