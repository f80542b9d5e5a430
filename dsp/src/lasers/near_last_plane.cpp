// The dots near where the last plane put them (docs/estimator.md, "Height
// from the laser dots", step 5): a standing car on sharp asphalt shows
// white grains as bright and as small as a dot on every track, so that no
// plane of this frame's brightest spots holds. The ground under a standing
// car does not move, so a grain is as bright as it was in the last frame,
// while the dots move with the body: along each track, what brightened
// since the last frame (this frame's response less the last one's) shows
// the dots where they are now. The body's heave moves all four together,
// by the same height (the tilt changes little in a frame): the height
// change that lines up the four brightenings best, within what
// Thresholds::max_height_rate_mm_per_s allows since the last plane, gives
// each dot's place. Each must stand out there as a dot does in step 2, by
// its brightening too, and the four must agree on one plane as four found
// dots do; or, with one dot on a stone too dark to show it, the other
// three's plane must put it where the heave put it, with no brightening
// beside. A grain taken for a dot by step 2 is masked beside it. Where the
// last frame as it was shows no plane, the same against the last plane's
// frame scaled by the height change (the heave scales the image of the
// ground, and the grains' edges left in the plain difference hide a dot on
// a dark stone). Not where the height changed so fast that the dots smeared
// along their tracks within the exposure (Thresholds::max_smear_sigmas).
#include <algorithm>
#include <array>
#include <cmath>

#include "dot_constants.hpp"
#include "gvs/dsp/ground_plane.hpp"
#include "gvs/dsp/laser_dots.hpp"

namespace gvs::dsp {
namespace {

/// Samples either side of where the height change puts a dot: the tilt's
/// change within a frame and the rounding.
constexpr long kSideSamples = 2;
constexpr std::size_t kBeams = 4;
/// The scaled look counts only where the last plane's frame, scaled,
/// explains the ground along every track: the brightenings' robust spread
/// at most this share of the responses' own. On the standing ground of the
/// stored `brake` runs it is 0.15-0.4 (what is left is the sensor's noise);
/// on ground that moved since (1-2 km/h in `const`) 1.7-2.2, as the
/// difference of two unrelated textures gives (sqrt 2 and more).
constexpr double kMaxUnexplainedSpread = 0.5;

}  // namespace

void LaserDotFinder::remember_plane(const cv::Mat& gray, const LaserDotResult& out, std::int64_t t_ns) {
  // Three found dots fix the plane; a beam whose dot was not found meets it there.
  std::array<core::Vec3, 3> p{};
  std::size_t m = 0;
  for (std::size_t k = 0; k < lasers_.count && m < 3; ++k)
    if (out.dots[k].found) p[m++] = out.dots[k].ground_mm;
  has_prior_ = false;
  if (m < 3) return;
  for (std::size_t k = 0; k < lasers_.count; ++k) {
    const LaserDot& d = out.dots[k];
    if (d.found) prior_along_px_[k] = tracks_[k].along_px(d.row, d.col);
    else if (!along_where_plane_meets(k, p[0], p[1], p[2], prior_along_px_[k])) return;
  }
  has_prior_ = true;
  prior_t_ns_ = t_ns;
  gray.copyTo(reference_gray_);
  reference_height_mm_ = out.ride.height_mm;
  has_reference_ = true;
}

LaserDotFinder::Brightened LaserDotFinder::near_the_last_plane(const cv::Mat& gray, double age_s, double exposure_us,
                                                               LaserDotResult& out) {
  // First against the last frame as it was; then, where that shows no
  // plane, against the last plane's frame scaled by the height change the
  // first look found: a heave of 1 mm in 60 scales the image by 1.7 %,
  // moving a grain at the frame's edge by 4 px, and the grains' edges
  // left in the difference of the frames as they are bury a dot on a dark
  // stone.
  for (std::size_t k = 0; k < kBeams; ++k) {
    const std::size_t n = tracks_[k].row.size();
    for (std::size_t i = 0; i < n; ++i) brightening_[k][i] = responses_[k][i] - last_responses_[k][i];
  }
  const double reach_mm = thresholds_.max_height_rate_mm_per_s * age_s + thresholds_.prior_margin_mm;
  HeightChange change;
  if (!brightened_height_change(age_s, exposure_us, reach_mm, change)) return Brightened::none;
  const std::size_t dots = plane_where_brightened(gray, change.dh_mm, out);
  if (dots > 0) return dots == kBeams ? Brightened::four : Brightened::three;
  if (!has_reference_) return Brightened::none;
  rescale_reference(reference_height_mm_ + change.scale_dh_mm);
  for (std::size_t k = 0; k < kBeams; ++k) {
    const std::size_t n = tracks_[k].row.size();
    track_responses(rescaled_, k, reference_responses_[k], scratch_backgrounds_);
    for (std::size_t i = 0; i < n; ++i) brightening_[k][i] = responses_[k][i] - reference_responses_[k][i];
  }
  if (!brightened_height_change(age_s, exposure_us, reach_mm, change)) return Brightened::none;
  // Only where the scaled frame explains the ground: the ground has not
  // moved, and the scale is right.
  for (std::size_t k = 0; k < kBeams; ++k)
    if (brightening_spread_[k] > kMaxUnexplainedSpread * spread_[k]) return Brightened::none;
  return plane_where_brightened(gray, change.dh_mm, out) > 0 ? Brightened::scaled : Brightened::none;
}

double LaserDotFinder::brightening_near(std::size_t k, double along, std::size_t& sample) const {
  const auto n = static_cast<long>(tracks_[k].row.size());
  const long centre = std::lround(along);
  double best = -1e300;
  for (long i = std::max(0L, centre - kSideSamples); i <= std::min(n - 1, centre + kSideSamples); ++i) {
    if (brightening_[k][static_cast<std::size_t>(i)] > best) {
      best = brightening_[k][static_cast<std::size_t>(i)];
      sample = static_cast<std::size_t>(i);
    }
  }
  return best;
}

bool LaserDotFinder::brightened_height_change(double age_s, double exposure_us, double reach_mm, HeightChange& change) {
  // The brightening's median and robust spread along each track.
  for (std::size_t k = 0; k < kBeams; ++k)
    robust_spread(brightening_[k], tracks_[k].row.size(), brightening_median_[k], brightening_spread_[k]);
  // The height change that lines up the four brightenings best, in steps
  // of half a pixel along the tracks: the first of the best (each dot is
  // then taken from a window of 5 samples) and the middle of their run.
  double px_per_mm = 0.0;
  for (std::size_t k = 0; k < kBeams; ++k) px_per_mm = std::max(px_per_mm, tracks_[k].px_per_mm_height);
  const double step_mm = 0.5 / px_per_mm;
  double best_score = -1e300;
  double last_best_mm = 0.0;
  change.dh_mm = 0.0;
  for (double dh = -reach_mm; dh <= reach_mm; dh += step_mm) {
    double score = 0.0;
    for (std::size_t k = 0; k < kBeams; ++k) {
      std::size_t sample = 0;
      score += brightening_near(k, prior_along_px_[k] + dh * tracks_[k].px_per_mm_height, sample);
    }
    if (score > best_score) {
      best_score = score;
      change.dh_mm = last_best_mm = dh;
    } else if (score == best_score && dh - last_best_mm <= 1.5 * step_mm) {
      last_best_mm = dh;
    }
  }
  change.scale_dh_mm = 0.5 * (change.dh_mm + last_best_mm);
  // How far each dot ran along its track while the light lasted, at the
  // rate the height changed since the last plane.
  const double rate_mm_per_us = std::abs(change.dh_mm) / (age_s * 1e6);
  for (std::size_t k = 0; k < kBeams; ++k) {
    const Track& t = tracks_[k];
    if (smeared(t, rate_mm_per_us * exposure_us * t.px_per_mm_height)) return false;
  }
  return true;
}

std::size_t LaserDotFinder::plane_where_brightened(const cv::Mat& gray, double dh_mm, LaserDotResult& out) {
  const auto& median = brightening_median_;
  const auto& spread = brightening_spread_;
  std::array<Candidate, kBeams> dot{};
  std::array<std::size_t, kBeams> sample{};
  std::array<core::Vec3, kBeams> p{};
  std::size_t appeared = 0;
  std::size_t missing = kBeams;
  for (std::size_t k = 0; k < kBeams; ++k) {
    // The most brightened sample where the height change puts dot k.
    brightening_near(k, prior_along_px_[k] + dh_mm * tracks_[k].px_per_mm_height, sample[k]);
    if (newly_there(k, sample[k], median[k], spread[k]) && measure(gray, k, sample[k], dot[k]) == DotStatus::found) {
      p[appeared++] = dot[k].ground_mm;
    } else {
      missing = k;
    }
  }
  core::RideHeight ride;
  if (appeared == kBeams) {
    double residual_mm = 0.0;
    ride = ground_from_fit(p.data(), kBeams, camera_.mount_yaw_deg, residual_mm);
    if (residual_mm > thresholds_.max_plane_residual_mm) return 0;
  } else if (appeared == kBeams - 1) {
    // One dot on a patch too dark to show it: the other three moved together
    // by the heave, and their plane must put the fourth where the heave put
    // it (each of the three lies within kSideSamples of its own place, so
    // the fourth within twice that), with no brightening beside that point
    // (the fourth dot elsewhere: one of the three is not a dot).
    double along = 0.0;
    if (!along_where_plane_meets(missing, p[0], p[1], p[2], along)) return 0;
    const double heave_along = prior_along_px_[missing] + dh_mm * tracks_[missing].px_per_mm_height;
    if (std::abs(along - heave_along) > static_cast<double>(2 * kSideSamples)) return 0;
    if (brightened_beside(missing, along, median[missing], spread[missing])) return 0;
    ride = ground_from_points(p[0], p[1], p[2], camera_.mount_yaw_deg);
  } else {
    return 0;
  }
  if (!plausible(ride)) return 0;
  // The spot step 2 took for a dot stays masked as its rival.
  for (std::size_t k = 0; k < kBeams; ++k) {
    if (k != missing) {
      take_at(k, sample[k], dot[k], out.dots[k]);
    } else {
      out.dots[k].found = false;
    }
  }
  out.ride = ride;
  return appeared;
}

bool LaserDotFinder::brightened_beside(std::size_t k, double along, double median, double spread) const {
  const auto n = static_cast<long>(tracks_[k].row.size());
  return dots::shows_beside(std::lround(along), kSideSamples, n,
                            [&](std::size_t i) { return newly_there(k, i, median, spread); });
}

void LaserDotFinder::rescale_reference(double height_now_mm) {
  // A point of level ground at X mm from the optical axis is imaged at
  // c + f X / h (pinhole; f in px): at height h1 a pixel x shows what the
  // reference frame at h0 showed at c + (x - c) h1 / h0. Bilinear, over the
  // pixels the tracks' responses read (a tenth of the frame).
  const auto s = static_cast<float>(height_now_mm / reference_height_mm_);
  const float rc = 0.5f * static_cast<float>(reference_gray_.rows - 1);
  const float cc = 0.5f * static_cast<float>(reference_gray_.cols - 1);
  const int last_r = reference_gray_.rows - 1, last_c = reference_gray_.cols - 1;
  for (std::size_t k = 0; k < lasers_.count; ++k) {
    for (const Track::RowSpan& span : tracks_[k].pixels) {
      const int r = span.row;
      const float y = std::clamp(rc + (static_cast<float>(r) - rc) * s, 0.0f, static_cast<float>(last_r));
      const int r0 = std::min(static_cast<int>(y), last_r - 1);
      const float fy = y - static_cast<float>(r0);
      const std::uint8_t* a = reference_gray_.ptr<std::uint8_t>(r0);
      const std::uint8_t* b = reference_gray_.ptr<std::uint8_t>(r0 + 1);
      auto* o = rescaled_.ptr<std::uint8_t>(r);
      for (int c = span.first_col; c <= span.last_col; ++c) {
        const float x = std::clamp(cc + (static_cast<float>(c) - cc) * s, 0.0f, static_cast<float>(last_c));
        const int c0 = std::min(static_cast<int>(x), last_c - 1);
        const float fx = x - static_cast<float>(c0);
        const float top = a[c0] + fx * static_cast<float>(a[c0 + 1] - a[c0]);
        const float bottom = b[c0] + fx * static_cast<float>(b[c0 + 1] - b[c0]);
        o[c] = static_cast<std::uint8_t>(top + fy * (bottom - top) + 0.5f);
      }
    }
  }
}

}  // namespace gvs::dsp
