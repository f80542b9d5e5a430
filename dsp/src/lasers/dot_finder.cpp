// See gvs/dsp/laser_dots.hpp and docs/estimator.md, "Height from the laser dots":
// steps 2-4 and the mask (the tracks and step 1: tracks.cpp; step 5: near_last_plane.cpp).
#include <algorithm>
#include <array>
#include <cmath>

#include "dot_constants.hpp"
#include "gvs/dsp/ground_plane.hpp"
#include "gvs/dsp/laser_dots.hpp"

namespace gvs::dsp {

using namespace dots;

void LaserDotFinder::find_one(const cv::Mat& gray, std::size_t k, LaserDot& dot) {
  const Track& t = tracks_[k];
  const std::size_t n = t.row.size();
  std::vector<double>& resp = responses_[k];
  std::vector<double>& bgs = backgrounds_[k];
  track_responses(gray, k, resp, bgs);
  std::size_t best = 0;
  for (std::size_t i = 0; i < n; ++i)
    if (resp[i] > resp[best]) best = i;
  // 2. Is it clearly there? Robust spread of the track's responses (median
  //    absolute deviation: the asphalt's texture and the sensor's noise).
  double median = 0.0;
  double spread = 0.0;
  robust_spread(resp, n, median, spread);
  median_[k] = median;
  spread_[k] = spread;
  const double peak = resp[best] - median;
  const double exclusion = kWindowSigmas * t.sigma_along_px + 2.0;
  std::size_t rival = n;
  for (std::size_t i = 0; i < n; ++i) {
    if (std::abs(static_cast<double>(i) - static_cast<double>(best)) <= exclusion) continue;
    if (rival == n || resp[i] > resp[rival]) rival = i;
  }
  dot.contrast_dn = resp[best];
  dot.peak_sigmas = spread > 0.0 ? peak / spread : 0.0;
  dot.rival_fraction = rival < n && peak > 0.0 ? (resp[rival] - median) / peak : 0.0;
  const bool bright = resp[best] >= thresholds_.min_contrast_dn && peak >= thresholds_.min_sigmas * spread;
  const bool contested = rival < n && resp[rival] - median >= thresholds_.max_rival_fraction * peak;
  if (bright) {
    dot.masked = true;
    dot.mask_row = t.row[best];
    dot.mask_col = t.col[best];
    dot.mask_background_dn = bgs[best];
    if (contested) {
      dot.rival = true;
      dot.rival_row = t.row[rival];
      dot.rival_col = t.col[rival];
      dot.rival_background_dn = bgs[rival];
    }
  }
  dot.status = !bright ? DotStatus::faint : DotStatus::contested;
  if (!bright) return;
  if (contested) {
    // Both measured: the ground plane may tell which is the dot (find()).
    dot.alternatives = 0;
    for (const std::size_t i : {best, rival}) {
      Candidate& cand = dot.candidates[dot.alternatives];
      if (measure(gray, k, i, cand) != DotStatus::found) return;  // one unmeasurable: leave it contested
      ++dot.alternatives;
    }
    return;
  }
  Candidate cand;
  dot.status = measure(gray, k, best, cand);
  if (dot.status != DotStatus::found) return;
  dot.take(cand);
  dot.mask_row = cand.row;
  dot.mask_col = cand.col;
}

DotStatus LaserDotFinder::measure(const cv::Mat& gray, std::size_t k, std::size_t sample, Candidate& out) const {
  const Track& t = tracks_[k];
  // 3. Centroid of the light over the ground around it, weighted with the
  //    spot's own Gaussian centred on the current estimate (a matched
  //    centroid: pixels far out, mostly asphalt and noise, count little),
  //    in a window of +-3 sigma, four times from the peak.
  const double bg = backgrounds_[k][sample];
  double rc = t.row[sample], cc = t.col[sample];
  for (int iter = 0; iter < 4; ++iter) {
    const int r0 = static_cast<int>(std::lround(rc)), c0 = static_cast<int>(std::lround(cc));
    double sw = 0.0, sr = 0.0, sc = 0.0;
    for (const Offset& o : t.window) {
      const int r = r0 + o.dr, c = c0 + o.dc;
      if (r < 0 || c < 0 || r >= gray.rows || c >= gray.cols) return DotStatus::at_edge;  // not measurable
      const double light = gray.at<std::uint8_t>(r, c) - bg;
      if (light <= 0.0) continue;
      const double y = r - rc, x = c - cc;
      const double along = (y * t.er + x * t.ec) / t.sigma_along_px;
      const double across = (-y * t.ec + x * t.er) / t.sigma_across_px;
      const double w = light * std::exp(-0.5 * (along * along + across * across) / (kWeightSigmas * kWeightSigmas));
      sw += w;
      sr += w * r;
      sc += w * c;
    }
    if (!(sw > 0.0)) return DotStatus::at_edge;
    rc = sr / sw;
    cc = sc / sw;
  }
  // 4. On its track? (A stone beside the track pulls the centroid off it.)
  const double across = -(rc - t.row0) * t.ec + (cc - t.col0) * t.er;
  if (std::abs(across) > thresholds_.max_off_track_px) return DotStatus::off_track;
  if (!triangulate(lasers_.beams[k], core::pixel_ray(camera_, nominal_height_mm_, rc, cc), out.ground_mm))
    return DotStatus::at_edge;
  out.row = rc;
  out.col = cc;
  return DotStatus::found;
}

void LaserDotFinder::take_at(std::size_t k, std::size_t sample, const Candidate& c, LaserDot& d) const {
  const auto near = [&c](double row, double col) { return std::hypot(row - c.row, col - c.col) <= 2.0; };
  if (d.masked && !near(d.mask_row, d.mask_col) && (!d.rival || near(d.rival_row, d.rival_col))) {
    d.rival = true;
    d.rival_row = d.mask_row;
    d.rival_col = d.mask_col;
    d.rival_background_dn = d.mask_background_dn;
  }
  d.masked = true;
  d.mask_row = c.row;
  d.mask_col = c.col;
  d.mask_background_dn = backgrounds_[k][sample];
  d.contrast_dn = responses_[k][sample];
  d.peak_sigmas = spread_[k] > 0.0 ? (d.contrast_dn - median_[k]) / spread_[k] : 0.0;
  d.take(c);
}

bool LaserDotFinder::plausible(const core::RideHeight& ride) const {
  return ride.has_height && ride.height_mm >= lasers_.min_height_mm && ride.height_mm <= lasers_.max_height_mm &&
         std::hypot(ride.pitch_deg, ride.roll_deg) <= thresholds_.max_tilt_deg;
}

LaserDotResult LaserDotFinder::detect(const cv::Mat& gray) {
  LaserDotResult out;
  if (gray.type() != CV_8UC1 || gray.rows != camera_.height_px || gray.cols != camera_.width_px) return out;
  for (std::size_t k = 0; k < lasers_.count; ++k) find_one(gray, k, out.dots[k]);
  if (lasers_.count >= 3) resolve(gray, out);
  for (std::size_t k = 0; k < lasers_.count; ++k)
    if (out.dots[k].found) ++out.found;
  return out;
}

void LaserDotFinder::withhold_doubtful_tilt(LaserDotResult& out) const {
  if (!out.ride.has_tilt()) return;
  std::array<core::Vec3, core::LaserGeometry::kMaxBeams> points{};
  std::size_t n = 0;
  for (std::size_t k = 0; k < lasers_.count; ++k)
    if (out.dots[k].found) points[n++] = out.dots[k].ground_mm;
  // Four dots show their own disagreement; three show none, and each angle
  // is judged by how far the dots' usual scatter moves it.
  if (n >= 4) {
    double residual_mm = 0.0;
    (void)ground_from_fit(points.data(), n, camera_.mount_yaw_deg, residual_mm);
    if (tilt_doubt_deg(points.data(), n, residual_mm) > thresholds_.max_tilt_doubt_deg)
      out.ride.has_pitch = out.ride.has_roll = false;
    return;
  }
  const TiltSigma sigma = tilt_sigma_deg(points.data(), n, thresholds_.dot_scatter_mm, camera_.mount_yaw_deg);
  if (sigma.pitch_deg > thresholds_.max_tilt_sigma_deg) out.ride.has_pitch = false;
  if (sigma.roll_deg > thresholds_.max_tilt_sigma_deg) out.ride.has_roll = false;
}

bool LaserDotFinder::smeared_dots(const LaserDotResult& out, double age_s, double exposure_us) const {
  for (std::size_t k = 0; k < lasers_.count; ++k) {
    const LaserDot& d = out.dots[k];
    if (!d.found) continue;
    const Track& t = tracks_[k];
    const double px_per_s = std::abs(t.along_px(d.row, d.col) - prior_along_px_[k]) / age_s;
    if (smeared(t, px_per_s * exposure_us * 1e-6)) return true;
  }
  return false;
}

LaserDotResult LaserDotFinder::find(const cv::Mat& gray) {
  LaserDotResult out = detect(gray);
  withhold_doubtful_tilt(out);
  return out;
}

LaserDotResult LaserDotFinder::find(const cv::Mat& gray, std::int64_t t_ns, double exposure_us) {
  LaserDotResult out = detect(gray);
  const double age_s = static_cast<double>(t_ns - prior_t_ns_) * 1e-9;
  if (has_prior_ && !(age_s > 0.0 && age_s <= thresholds_.max_prior_age_s)) has_prior_ = false;
  const double since_last_s = static_cast<double>(t_ns - last_responses_t_ns_) * 1e-9;
  const bool last_frame = has_last_responses_ && since_last_s > 0.0 && since_last_s <= thresholds_.max_prior_age_s;
  Brightened brightened = Brightened::none;
  if (!out.ride.has_height && has_prior_ && last_frame && lasers_.count == 4) {
    brightened = near_the_last_plane(gray, age_s, exposure_us, out);
    if (out.ride.has_height) {
      out.found = 0;
      for (std::size_t k = 0; k < lasers_.count; ++k)
        if (out.dots[k].found) ++out.found;
    }
  }
  const bool smeared = out.ride.has_tilt() && has_prior_ && age_s > 0.0 && smeared_dots(out, age_s, exposure_us);
  if (out.ride.has_height && out.ride.has_tilt()) remember_plane(gray, out, t_ns);
  for (std::size_t k = 0; k < lasers_.count; ++k) std::copy(responses_[k].begin(), responses_[k].end(), last_responses_[k].begin());
  has_last_responses_ = true;
  last_responses_t_ns_ = t_ns;
  // After the plane is kept: step 5 steers by where the dots were.
  withhold_doubtful_tilt(out);
  // Three dots where they brightened are a standing car's on sharp ground,
  // whose reflectance moves a centroid about twice as far as on the moving
  // ground dot_scatter_mm stands for: either angle's sigma would pass
  // max_tilt_sigma_deg. Dots found only against the scaled frame lie on
  // stones dark enough to hide them from the first look, where the ground
  // pulls a faint dot's centroid furthest. Their plane still guides the
  // next frame.
  if (smeared || brightened == Brightened::three || brightened == Brightened::scaled)
    out.ride.has_pitch = out.ride.has_roll = false;
  return out;
}

void LaserDotFinder::resolve(const cv::Mat& gray, LaserDotResult& out) const {
  // Each dot: found (one choice), contested with two measured candidates
  // (two choices), else absent. A plane outside the searched heights, or
  // tilted beyond max_tilt_deg, is not the ground; a contested dot is
  // resolved when only one of its candidates gives a plausible plane (a
  // rival elsewhere on the track moves the plane by millimetres and
  // degrees), and left unfound when both do. Four dots must also agree on
  // one plane (max_plane_residual_mm); when they do not, the one set of
  // three that makes a plausible plane is taken, and with none or several
  // there is no height. Three dots of a four-beam head make a plane nothing
  // checks: it is taken only when none of them has a rival (a track with a
  // grain as bright as a dot is where the wrong planes came from).
  constexpr std::size_t kMax = core::LaserGeometry::kMaxBeams;
  std::array<std::size_t, kMax> choices{};
  unsigned present = 0;  // bit k: dot k has at least one candidate
  for (std::size_t k = 0; k < lasers_.count; ++k) {
    const LaserDot& d = out.dots[k];
    if (d.found) choices[k] = 1;
    else if (d.status == DotStatus::contested && d.alternatives == 2) choices[k] = 2;
    if (choices[k] > 0) present |= 1u << k;
  }
  auto point = [&](std::size_t k, std::size_t c) -> const core::Vec3& {
    return out.dots[k].found ? out.dots[k].ground_mm : out.dots[k].candidates[c].ground_mm;
  };
  struct Solution {
    std::size_t count = 0;  ///< acceptable planes
    unsigned used = 0;
    std::array<std::size_t, kMax> pick{};
    core::RideHeight ride;
  };
  // Every choice of candidates for the dots in `used` (at most 2^4).
  auto solve = [&](unsigned used, Solution& best) {
    std::array<std::size_t, kMax> dots{};
    std::size_t m = 0;
    for (std::size_t k = 0; k < kMax; ++k)
      if (used & (1u << k)) dots[m++] = k;
    std::size_t combos = 1;
    for (std::size_t i = 0; i < m; ++i) combos *= choices[dots[i]];
    if (m == 3 && lasers_.count == 4 && combos > 1) return;  // unchecked, and a rival on a track
    for (std::size_t combo = 0; combo < combos; ++combo) {
      std::array<std::size_t, kMax> pick{};
      std::array<core::Vec3, kMax> p{};
      for (std::size_t i = 0, rest = combo; i < m; ++i) {
        pick[dots[i]] = rest % choices[dots[i]];
        rest /= choices[dots[i]];
        p[i] = point(dots[i], pick[dots[i]]);
      }
      core::RideHeight r;
      if (m == 3) {
        r = ground_from_points(p[0], p[1], p[2], camera_.mount_yaw_deg);
      } else {
        double residual_mm = 0.0;
        r = ground_from_fit(p.data(), m, camera_.mount_yaw_deg, residual_mm);
        if (residual_mm > thresholds_.max_plane_residual_mm) continue;
      }
      if (!plausible(r)) continue;
      ++best.count;
      best.used = used;
      best.pick = pick;
      best.ride = r;
    }
  };
  const auto present_count = static_cast<std::size_t>(std::popcount(present));
  if (present_count < 3) return;
  Solution s;
  solve(present, s);
  if (s.count == 0 && present_count == 4) {
    for (std::size_t drop = 0; drop < 4; ++drop) solve(present & ~(1u << drop), s);
  }
  if (s.count == 0 && lasers_.count == 4) {
    fourth_where_three_put_it(gray, out);
    return;
  }
  if (s.count != 1) return;
  for (std::size_t k = 0; k < lasers_.count; ++k) {
    LaserDot& d = out.dots[k];
    if (!(s.used & (1u << k))) {
      if (d.found) {  // found, but off the others' plane: a bright grain, still masked
        d.found = false;
        d.status = DotStatus::off_plane;
      }
      continue;
    }
    if (!d.found) d.take(d.candidates[s.pick[k]]);
  }
  out.ride = s.ride;
  // Three dots of four: the fourth may be there, outshone by a grain taken
  // for it; found where they put it, it checks them (and fixes the tilt).
  if (lasers_.count == 4 && std::popcount(s.used) == 3) {
    fourth_where_three_put_it(gray, out);
    // Not there, but a dot beside it: the three's plane is off. No height.
    if (fourth_beside_where_three_put_it(out)) out.ride = core::RideHeight{};
  }
}

void LaserDotFinder::mask(const LaserDotResult& result, cv::Mat& gray) const {
  auto blend = [&](const Track& t, double row, double col, double background) {
    const int r0 = static_cast<int>(std::lround(row)), c0 = static_cast<int>(std::lround(col));
    const double fr = row - r0, fc = col - c0;
    const int reach = static_cast<int>(std::ceil(kMaskEdgeSigmas * t.sigma_along_px)) + 1;
    for (int dr = -reach; dr <= reach; ++dr) {
      const int r = r0 + dr;
      if (r < 0 || r >= gray.rows) continue;
      auto* line = gray.ptr<std::uint8_t>(r);
      for (int dc = -reach; dc <= reach; ++dc) {
        const int c = c0 + dc;
        if (c < 0 || c >= gray.cols) continue;
        const double y = dr - fr, x = dc - fc;
        const double along = (y * t.er + x * t.ec) / t.sigma_along_px;
        const double across = (-y * t.ec + x * t.er) / t.sigma_across_px;
        const double rho = std::sqrt(along * along + across * across);
        if (rho >= kMaskEdgeSigmas) continue;
        // Weight 1 inside 3 sigma, a raised-cosine taper to 0 at 4.5 sigma.
        const double w = rho <= kMaskFullSigmas
                             ? 1.0
                             : 0.5 * (1.0 + std::cos(core::kPi * (rho - kMaskFullSigmas) /
                                                     (kMaskEdgeSigmas - kMaskFullSigmas)));
        const double v = background + (line[c] - background) * (1.0 - w);
        line[c] = static_cast<std::uint8_t>(std::clamp(std::lround(v), 0L, 255L));
      }
    }
  };
  for (std::size_t k = 0; k < lasers_.count; ++k) {
    const LaserDot& d = result.dots[k];
    if (d.masked) blend(tracks_[k], d.mask_row, d.mask_col, d.mask_background_dn);
    if (d.rival) blend(tracks_[k], d.rival_row, d.rival_col, d.rival_background_dn);
  }
}

}  // namespace gvs::dsp
