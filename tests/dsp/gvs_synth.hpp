// Synthetic ground frames for the gvs estimator's unit tests: a periodic
// random asphalt-like texture, seen through a camera that moves (shift,
// rotation), blurs (continuous exposure) or double-exposes (two pulses), with
// temporal noise and fixed-pattern noise. Independent of the simulator.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

namespace gvs::test {

/// A periodic random texture (size x size), zero mean, unit variance,
/// positively skewed (bright stones): exp() of a band-limited Gaussian field.
inline cv::Mat make_texture(int size, std::uint64_t seed, double grain_px = 1.3) {
  cv::RNG rng(seed);
  cv::Mat noise(size, size, CV_32F);
  rng.fill(noise, cv::RNG::NORMAL, 0.0, 1.0);
  cv::Mat spec;
  cv::dft(noise, spec, cv::DFT_COMPLEX_OUTPUT);
  for (int r = 0; r < size; ++r) {
    const int fr = r < size / 2 ? r : r - size;
    for (int c = 0; c < size; ++c) {
      const int fc = c < size / 2 ? c : c - size;
      const double k2 = (fr * fr + fc * fc) * (2.0 * CV_PI / size) * (2.0 * CV_PI / size);
      // Fine grain plus a coarser component.
      const double g = std::exp(-0.5 * k2 * grain_px * grain_px) +
                       0.5 * std::exp(-0.5 * k2 * 16.0 * grain_px * grain_px);
      spec.at<cv::Vec2f>(r, c) *= static_cast<float>(g);
    }
  }
  cv::Mat field;
  cv::dft(spec, field, cv::DFT_INVERSE | cv::DFT_REAL_OUTPUT | cv::DFT_SCALE);
  cv::Scalar mean;
  cv::Scalar stddev;
  cv::meanStdDev(field, mean, stddev);
  field = (field - mean[0]) / stddev[0];
  cv::Mat skewed;
  cv::exp(field * 0.6, skewed);
  cv::meanStdDev(skewed, mean, stddev);
  return (skewed - mean[0]) / stddev[0];
}

/// The texture as seen with the ground displaced by p = (row, col) px in the
/// image and the content rotated by phi rad (about the frame centre; a ground
/// point at column offset c moves by phi*c rows, as a CCW yaw does).
inline void accumulate_view(const cv::Mat& tex, cv::Size frame, double p_row, double p_col,
                            double phi, double weight, cv::Mat& acc) {
  const double n = tex.rows;
  p_row = std::fmod(p_row, n);
  p_col = std::fmod(p_col, n);
  const double rc = (frame.height - 1) / 2.0;
  const double cc = (frame.width - 1) / 2.0;
  const double cs = std::cos(phi);
  const double sn = std::sin(phi);
  // src = R(-phi) (dst - centre) + centre - p   (x = col, y = row)
  // Content rotates: d_row = +phi * c_offset, d_col = -phi * r_offset.
  cv::Matx23d m(cs, sn, 0.0, -sn, cs, 0.0);
  m(0, 2) = cc - (cs * cc + sn * rc) - p_col + n / 4;
  m(1, 2) = rc - (-sn * cc + cs * rc) - p_row + n / 4;
  cv::Mat view;
  cv::warpAffine(tex, view, m, frame, cv::INTER_CUBIC | cv::WARP_INVERSE_MAP, cv::BORDER_WRAP);
  cv::scaleAdd(view, weight, acc, acc);
}

/// Light during one frame: pulses of (start, duration) in "image travel"
/// units: the ground moves by v_px per unit of time.
struct Pulse {
  double start = 0.0;
  double duration = 0.0;
  double energy_per_time = 1.0;
};

struct Sensor {
  double mean_grey = 110.0;
  double contrast_grey = 30.0;
  double noise_grey = 1.5;  ///< temporal
  double fpn_grey = 2.0;    ///< fixed pattern
  std::uint64_t fpn_seed = 99;
  double falloff = 0.0;  ///< the ring light's brightness loss at the frame's corners (0.3 = 30 %)
};

inline cv::Mat sensor_frame(const cv::Mat& texture, const Sensor& sensor, std::uint64_t noise_seed);

/// Renders one 8-bit frame: the ground at p0 (px) at the frame start moving
/// with image velocity (v_row, v_col) px per time unit, rotating by
/// omega rad per time unit; pulses say when light reaches the sensor.
inline cv::Mat render_frame(const cv::Mat& tex, cv::Size frame, double p0_row, double p0_col,
                            double phi0, double v_row, double v_col, double omega,
                            const std::vector<Pulse>& pulses, const Sensor& sensor,
                            std::uint64_t noise_seed) {
  cv::Mat acc = cv::Mat::zeros(frame, CV_32F);
  double total = 0.0;
  for (const Pulse& p : pulses) {
    const double travel = std::hypot(v_row, v_col) * p.duration;
    const int steps = std::max(1, static_cast<int>(std::ceil(travel * 2.0)));
    for (int i = 0; i < steps; ++i) {
      const double t = p.start + p.duration * (i + 0.5) / steps;
      const double w = p.energy_per_time * (p.duration > 0.0 ? p.duration : 1.0) / steps;
      accumulate_view(tex, frame, p0_row + v_row * t, p0_col + v_col * t, phi0 + omega * t, w,
                      acc);
      total += w;
    }
  }
  // Brightness normalised to the total light (the LED is brighter for short pulses).
  acc /= total;
  return sensor_frame(acc, sensor, noise_seed);
}

/// The sensor's view of `texture` (zero mean, unit variance, CV_32F): grey
/// = mean + contrast x texture, times the ring light's fall-off, plus the
/// fixed pattern and temporal noise, rounded to 8 bits.
inline cv::Mat sensor_frame(const cv::Mat& texture, const Sensor& sensor, std::uint64_t noise_seed) {
  const cv::Size frame = texture.size();
  cv::Mat out = texture * sensor.contrast_grey + sensor.mean_grey;
  if (sensor.falloff > 0.0) {
    // Brightness 1 - falloff (r / r_corner)^2: the ring light's fall-off.
    const double rc = (frame.height - 1) / 2.0;
    const double cc = (frame.width - 1) / 2.0;
    const double r2_corner = rc * rc + cc * cc;
    for (int r = 0; r < frame.height; ++r) {
      auto* o = out.ptr<float>(r);
      for (int c = 0; c < frame.width; ++c) {
        const double r2 = (r - rc) * (r - rc) + (c - cc) * (c - cc);
        o[c] *= static_cast<float>(1.0 - sensor.falloff * r2 / r2_corner);
      }
    }
  }
  cv::RNG fpn_rng(sensor.fpn_seed);
  cv::Mat fpn(frame, CV_32F);
  fpn_rng.fill(fpn, cv::RNG::NORMAL, 0.0, sensor.fpn_grey);
  cv::RNG rng(noise_seed);
  cv::Mat noise(frame, CV_32F);
  rng.fill(noise, cv::RNG::NORMAL, 0.0, sensor.noise_grey);
  out += fpn + noise;
  cv::Mat gray;
  out.convertTo(gray, CV_8U);  // rounds and saturates to [0, 255]
  return gray;
}

/// One continuous exposure of `length` time units.
inline std::vector<Pulse> continuous(double length) { return {Pulse{0.0, length, 1.0}}; }

}  // namespace gvs::test
