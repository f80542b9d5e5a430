// See gvs/dsp/laser_calibration.hpp for the maths.
#include "gvs/dsp/laser_calibration.hpp"

#include <algorithm>
#include <cmath>

#include <opencv2/imgproc.hpp>

namespace gvs::dsp {

std::vector<BrightSpot> find_bright_spots(const cv::Mat& gray, double sigma_px, std::size_t max_spots) {
  cv::Mat f, centre, surround;
  gray.convertTo(f, CV_32F);
  cv::GaussianBlur(f, centre, cv::Size(), sigma_px);
  cv::GaussianBlur(f, surround, cv::Size(), 3.0 * sigma_px);
  const cv::Mat dog = centre - surround;
  const int gap = std::max(2, static_cast<int>(std::ceil(4.0 * sigma_px)));
  std::vector<BrightSpot> found;
  for (int r = gap; r < dog.rows - gap; ++r) {
    for (int c = gap; c < dog.cols - gap; ++c) {
      const float v = dog.at<float>(r, c);
      if (!(v > 0.0f)) continue;
      bool is_max = true;
      for (int dr = -gap; dr <= gap && is_max; ++dr)
        for (int dc = -gap; dc <= gap; ++dc)
          if ((dr != 0 || dc != 0) && dog.at<float>(r + dr, c + dc) >= v) {
            is_max = false;
            break;
          }
      if (is_max) found.push_back({static_cast<double>(r), static_cast<double>(c), static_cast<double>(v)});
    }
  }
  std::sort(found.begin(), found.end(), [](const BrightSpot& a, const BrightSpot& b) {
    return a.response_dn > b.response_dn;
  });
  if (found.size() > max_spots) found.resize(max_spots);
  // Matched centroid over the local background (the surround).
  for (BrightSpot& s : found) {
    const double bg = static_cast<double>(surround.at<float>(static_cast<int>(s.row), static_cast<int>(s.col)));
    double rc = s.row, cc = s.col;
    for (int iter = 0; iter < 4; ++iter) {
      double sw = 0.0, sr = 0.0, sc = 0.0;
      const int r0 = static_cast<int>(std::lround(rc)), c0 = static_cast<int>(std::lround(cc));
      for (int r = std::max(0, r0 - gap); r <= std::min(f.rows - 1, r0 + gap); ++r) {
        for (int c = std::max(0, c0 - gap); c <= std::min(f.cols - 1, c0 + gap); ++c) {
          const double light = static_cast<double>(f.at<float>(r, c)) - bg;
          if (light <= 0.0) continue;
          const double q = ((r - rc) * (r - rc) + (c - cc) * (c - cc)) / (sigma_px * sigma_px);
          const double w = light * std::exp(-0.5 * q);
          sw += w;
          sr += w * r;
          sc += w * c;
        }
      }
      if (!(sw > 0.0)) break;
      rc = sr / sw;
      cc = sc / sw;
    }
    s.row = rc;
    s.col = cc;
  }
  return found;
}

std::optional<LaserFit> fit_laser_geometry(const std::vector<HeightObservation>& observations,
                                           const core::CameraGeometry& camera, double nominal_height_mm,
                                           const core::LaserGeometry& prior, double exit_z_mm, double match_px) {
  LaserFit fit;
  fit.lasers = prior;
  double residual_sq = 0.0;
  std::size_t residual_n = 0;
  std::size_t heights_min = observations.size();
  for (std::size_t k = 0; k < prior.count; ++k) {
    const core::LaserBeam& beam = prior.beams[k];
    // Ground points of this beam: the spot nearest its predicted dot.
    std::vector<core::Vec3> points;
    for (const HeightObservation& obs : observations) {
      const core::Vec3 o = beam.origin_mm();
      const core::Vec3 u = beam.direction();
      const core::Vec3 expected = o + ((obs.height_mm + o.z) / -u.z) * u;
      double er = 0.0, ec = 0.0;
      core::head_to_pixel(camera, nominal_height_mm, expected, er, ec);
      const BrightSpot* best = nullptr;
      double best_d = match_px;
      for (const BrightSpot& s : obs.spots) {
        const double d = std::hypot(s.row - er, s.col - ec);
        if (d < best_d) {
          best_d = d;
          best = &s;
        }
      }
      if (!best) continue;
      points.push_back(obs.height_mm * core::pixel_ray(camera, nominal_height_mm, best->row, best->col));
    }
    heights_min = std::min(heights_min, points.size());
    if (points.size() < 2) return std::nullopt;
    // x = x0 + kx z, y = y0 + ky z: least squares in z.
    double mz = 0.0, mx = 0.0, my = 0.0;
    for (const core::Vec3& p : points) {
      mz += p.z;
      mx += p.x;
      my += p.y;
    }
    const double n = static_cast<double>(points.size());
    mz /= n;
    mx /= n;
    my /= n;
    double szz = 0.0, szx = 0.0, szy = 0.0;
    for (const core::Vec3& p : points) {
      szz += (p.z - mz) * (p.z - mz);
      szx += (p.z - mz) * (p.x - mx);
      szy += (p.z - mz) * (p.y - my);
    }
    if (!(szz > 1e-6)) return std::nullopt;  // all at one height
    const double kx = szx / szz, ky = szy / szz;
    const double x0 = mx - kx * mz, y0 = my - ky * mz;
    for (const core::Vec3& p : points) {
      residual_sq += std::pow(p.x - (x0 + kx * p.z), 2) + std::pow(p.y - (y0 + ky * p.z), 2);
      ++residual_n;
    }
    core::LaserBeam& out = fit.lasers.beams[k];
    out.tilt_deg = core::rad_to_deg(std::atan(std::hypot(kx, ky)));
    out.azimuth_deg = core::rad_to_deg(std::atan2(-ky, -kx));
    out.x_mm = x0 + kx * exit_z_mm;
    out.y_mm = y0 + ky * exit_z_mm;
    out.z_mm = exit_z_mm;
  }
  fit.heights_used = heights_min;
  fit.rms_residual_mm = residual_n > 0 ? std::sqrt(residual_sq / static_cast<double>(residual_n)) : 0.0;
  return fit;
}

}  // namespace gvs::dsp
