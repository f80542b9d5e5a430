// The fourth dot where three put it (docs/estimator.md, "Height from the
// laser dots", step 4): when no plane of the brightest candidates holds, or
// only one of three dots, each plausible plane of three predicts where the
// fourth beam meets the ground; if its track shows a dot there (bright by
// the same rule as any dot, only not the brightest: a white grain elsewhere
// on the track outshines it; and, behind three found dots, 3 robust sigmas
// for step 2's 4: a known place, not a whole track), the four are fitted and
// must agree as four found dots do.
// A grain is then masked beside the dot (on a contested track whose two
// spots both missed the plane, the dot is a third spot: it and the rival
// are masked, the grain taken first is ground again). A plane of three
// whose fourth dot is not there but shows a few pixels beside is off (one
// of the three a grain): fourth_beside_where_three_put_it.
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <vector>

#include "dot_constants.hpp"
#include "gvs/dsp/ground_plane.hpp"
#include "gvs/dsp/laser_dots.hpp"

namespace gvs::dsp {
namespace {

/// Samples either side of the predicted one searched for the dot: the
/// three dots' scatter moves the prediction by well under a pixel, a plane
/// tilted by max_tilt_deg through wrong dots by several.
constexpr int kSearchSamples = 2;

}  // namespace

void LaserDotFinder::fourth_where_three_put_it(const cv::Mat& gray, LaserDotResult& out) const {
  constexpr std::size_t kMax = core::LaserGeometry::kMaxBeams;
  struct Found {
    std::size_t fourth = 0;
    std::array<std::size_t, kMax> pick{};  ///< candidate of each of the three (0 for a found dot)
    std::size_t sample = 0;                ///< the fourth's sample on its track
    Candidate dot;
    core::RideHeight ride;
  };
  Found first;
  std::size_t distinct = 0;
  for (std::size_t fourth = 0; fourth < kMax; ++fourth) {
    std::array<std::size_t, 3> three{};
    std::array<std::size_t, 3> choices{};
    std::size_t m = 0;
    for (std::size_t k = 0; k < kMax; ++k) {
      if (k == fourth) continue;
      const LaserDot& d = out.dots[k];
      choices[m] = d.found ? 1 : (d.status == DotStatus::contested && d.alternatives == 2 ? 2 : 0);
      three[m++] = k;
    }
    if (choices[0] == 0 || choices[1] == 0 || choices[2] == 0) continue;
    const std::size_t n = tracks_[fourth].row.size();
    for (std::size_t combo = 0; combo < choices[0] * choices[1] * choices[2]; ++combo) {
      std::array<std::size_t, kMax> pick{};
      std::array<core::Vec3, 4> p{};
      for (std::size_t i = 0, rest = combo; i < 3; ++i) {
        pick[three[i]] = rest % choices[i];
        rest /= choices[i];
        const LaserDot& d = out.dots[three[i]];
        p[i] = d.found ? d.ground_mm : d.candidates[pick[three[i]]].ground_mm;
      }
      if (!plausible(ground_from_points(p[0], p[1], p[2], camera_.mount_yaw_deg))) continue;
      // The predicted sample: samples are 1 px apart along the track.
      double along = 0.0;
      if (!along_where_plane_meets(fourth, p[0], p[1], p[2], along)) continue;
      const long centre = std::lround(along);
      if (centre < 0 || centre >= static_cast<long>(n)) continue;
      const long last = std::min(static_cast<long>(n) - 1, centre + kSearchSamples);
      std::size_t best = n;
      for (long i = std::max(0L, centre - kSearchSamples); i <= last; ++i) {
        const auto si = static_cast<std::size_t>(i);
        if (best == n || responses_[fourth][si] > responses_[fourth][best]) best = si;
      }
      // The lower bar only where the three are dots step 2 found: among a
      // contested track's spots (grains as bright as a dot) a faint fourth
      // would choose a plane of grains as readily as the dots'.
      const bool three_found = choices[0] == 1 && choices[1] == 1 && choices[2] == 1;
      if (!stands_out(fourth, best, three_found ? thresholds_.min_sigmas_where_put : thresholds_.min_sigmas)) continue;
      Candidate c4;
      if (measure(gray, fourth, best, c4) != DotStatus::found) continue;
      p[3] = c4.ground_mm;
      double residual_mm = 0.0;
      const core::RideHeight ride = ground_from_fit(p.data(), 4, camera_.mount_yaw_deg, residual_mm);
      if (residual_mm > thresholds_.max_plane_residual_mm || !plausible(ride)) continue;
      // The same four dots reached from another three count once.
      if (distinct > 0 && std::abs(ride.height_mm - first.ride.height_mm) < thresholds_.max_plane_residual_mm &&
          std::abs(ride.pitch_deg - first.ride.pitch_deg) < 0.1 && std::abs(ride.roll_deg - first.ride.roll_deg) < 0.1)
        continue;
      if (++distinct == 1) first = Found{fourth, pick, best, c4, ride};
    }
  }
  if (distinct != 1) return;
  for (std::size_t k = 0; k < kMax; ++k) {
    LaserDot& d = out.dots[k];
    if (k != first.fourth) {
      if (!d.found) d.take(d.candidates[first.pick[k]]);
      continue;
    }
    take_at(k, first.sample, first.dot, d);
  }
  out.ride = first.ride;
}

bool LaserDotFinder::along_where_plane_meets(std::size_t k, const core::Vec3& p1, const core::Vec3& p2,
                                             const core::Vec3& p3, double& along_px) const {
  core::Vec3 point;
  if (!beam_on_plane(lasers_.beams[k], p1, p2, p3, point) || !(point.z < 0.0)) return false;
  double row = 0.0, col = 0.0;
  core::head_to_pixel(camera_, nominal_height_mm_, point, row, col);
  along_px = tracks_[k].along_px(row, col);
  return true;
}

bool LaserDotFinder::fourth_beside_where_three_put_it(const LaserDotResult& out) const {
  std::array<core::Vec3, 3> p{};
  std::size_t m = 0;
  std::size_t fourth = lasers_.count;
  for (std::size_t k = 0; k < lasers_.count; ++k) {
    if (!out.dots[k].found) fourth = k;
    else if (m < 3) p[m++] = out.dots[k].ground_mm;
  }
  if (m != 3 || fourth == lasers_.count) return false;
  double along = 0.0;
  if (!along_where_plane_meets(fourth, p[0], p[1], p[2], along)) return false;
  const std::vector<double>& response = responses_[fourth];
  const auto n = static_cast<long>(tracks_[fourth].row.size());
  const long centre = std::lround(along);
  double where_put = -std::numeric_limits<double>::infinity();
  for (long i = std::max(0L, centre - kSearchSamples); i <= std::min(n - 1, centre + kSearchSamples); ++i)
    where_put = std::max(where_put, response[static_cast<std::size_t>(i)]);
  // Step 2's bars, and brighter than the track where the three put the dot.
  return dots::shows_beside(centre, kSearchSamples, n, [&](std::size_t i) {
    return stands_out(fourth, i) && response[i] > where_put;
  });
}

}  // namespace gvs::dsp
