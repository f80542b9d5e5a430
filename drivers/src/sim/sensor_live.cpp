// Sensor::expose_live: the sensor model of sensor.cpp with cheaper Gaussian
// draws, for the live fast render (docs/simulator.md, "Live source").
#include <algorithm>
#include <array>
#include <cmath>

#include "hash.hpp"
#include "sensor.hpp"
#include "sensor_pixel.hpp"

namespace gvs::drivers::sim {
namespace {

constexpr int kTableBits = 12;
constexpr int kTableSize = 1 << kTableBits;

/// Standard normal quantiles at the centres of 4096 equal-probability bins
/// (inverse CDF by bisection on erfc; once, at first use).
const std::array<float, kTableSize>& normal_table() {
  static const std::array<float, kTableSize> table = [] {
    std::array<float, kTableSize> t{};
    for (int k = 0; k < kTableSize; ++k) {
      const double p = (k + 0.5) / kTableSize;
      double lo = -10.0, hi = 10.0;
      for (int it = 0; it < 80; ++it) {
        const double mid = 0.5 * (lo + hi);
        (0.5 * std::erfc(-mid / std::sqrt(2.0)) < p ? lo : hi) = mid;
      }
      t[static_cast<std::size_t>(k)] = static_cast<float>(0.5 * (lo + hi));
    }
    // Rescale so the table's variance is exactly 1 (the binning trims the tails).
    double var = 0.0;
    for (const float v : t) var += static_cast<double>(v) * static_cast<double>(v);
    const auto scale = static_cast<float>(1.0 / std::sqrt(var / kTableSize));
    for (float& v : t) v *= scale;
    return t;
  }();
  return table;
}

/// Five table normals per 64-bit draw.
class TableNormals {
 public:
  explicit TableNormals(std::uint64_t seed) : rng_(seed), table_(normal_table().data()) {}
  float normal() {
    if (left_ == 0) {
      bits_ = rng_.next();
      left_ = 5;
    }
    const float v = table_[bits_ & (kTableSize - 1)];
    bits_ >>= kTableBits;
    --left_;
    return v;
  }
  float uniformf() { return rng_.uniformf(); }

 private:
  detail::Rng rng_;
  const float* table_;
  std::uint64_t bits_ = 0;
  int left_ = 0;
};

}  // namespace

void Sensor::expose_live(const cv::Mat& reflectance, double e_per_reflectance, double gain_dn_per_e,
                         std::uint64_t noise_seed, cv::Mat& gray) const {
  gray.create(reflectance.rows, reflectance.cols, CV_8UC1);
  const PixelModel m = pixel_model(e_per_reflectance, gain_dn_per_e);
  for (int r = 0; r < reflectance.rows; ++r) {
    TableNormals normals(detail::hash_cell(noise_seed, 7, r, 0));
    expose_row(m, reflectance.ptr<float>(r), response_.ptr<float>(r), offset_.ptr<float>(r),
               gray.ptr<std::uint8_t>(r), reflectance.cols, normals);
  }
}

}  // namespace gvs::drivers::sim
