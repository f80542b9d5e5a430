// ORB frame difference, thesis 4.3 (direction) and 5.1 (speed).
#include <algorithm>
#include <cmath>

#include "gvs/dsp/vocabulary.hpp"
#include "gvs/dsp/thesis_orb.hpp"

namespace gvs::dsp::thesis {

OrbShift summarise_displacements(const std::vector<cv::Point2d>& d_row_col, const OrbConfig& config) {
  OrbShift s;
  s.match_count = static_cast<int>(d_row_col.size());
  if (s.match_count < config.min_matches || s.match_count == 0) return s;

  // Thesis 4.3: "all angles are averaged". A plain mean breaks where angles
  // wrap (179 deg and -179 deg average to 0), so we average unit vectors:
  //   mean angle = atan2(sum sin(theta_n), sum cos(theta_n)).
  // Thesis eq. 5.2: |x| = sqrt( (1/N) sum |x_n|^2 ).
  double sum_cos = 0.0;
  double sum_sin = 0.0;
  double sum_sq = 0.0;
  int counted = 0;
  for (const cv::Point2d& d : d_row_col) {
    const double len = std::hypot(d.x, d.y);
    sum_sq += len * len;
    if (len <= 0.0) continue;  // a zero vector has no angle
    sum_cos += d.x / len;      // theta_n = atan2(d_col, d_row): camera axes
    sum_sin += d.y / len;
    ++counted;
  }
  const double n = static_cast<double>(s.match_count);
  s.rms_px = std::sqrt(sum_sq / n);
  s.angle_consistency = counted > 0 ? std::hypot(sum_cos, sum_sin) / static_cast<double>(counted) : 0.0;
  s.angle_cam_deg = counted > 0 ? rad_to_deg(std::atan2(sum_sin, sum_cos)) : 0.0;
  s.d_row_px = s.rms_px * std::cos(deg_to_rad(s.angle_cam_deg));
  s.d_col_px = s.rms_px * std::sin(deg_to_rad(s.angle_cam_deg));
  // Standing still: every match has zero length, so the angle is undefined
  // but the (zero) displacement is measured.
  const double fill = std::min(1.0, n / static_cast<double>(std::max(1, config.matches_for_full_quality)));
  s.quality = (counted > 0 ? s.angle_consistency : 1.0) * fill;
  s.ok = true;
  return s;
}

OrbFrameDifference::OrbFrameDifference(const OrbConfig& config)
    : config_(config), orb_(cv::ORB::create(config.max_features)), matcher_(cv::NORM_HAMMING, /*crossCheck=*/true) {
  prev_keypoints_.reserve(static_cast<std::size_t>(config.max_features) * 2);
  cur_keypoints_.reserve(static_cast<std::size_t>(config.max_features) * 2);
  matches_.reserve(static_cast<std::size_t>(config.max_features) * 2);
}

void OrbFrameDifference::detect(const cv::Mat& gray, std::vector<cv::KeyPoint>& keypoints, cv::Mat& descriptors) {
  keypoints.clear();
  orb_->detectAndCompute(gray, cv::noArray(), keypoints, descriptors);
}

void OrbFrameDifference::set_previous(const cv::Mat& gray) {
  detect(gray, prev_keypoints_, prev_descriptors_);
  has_previous_ = true;
}

OrbShift OrbFrameDifference::measure_and_advance(const cv::Mat& gray) {
  detect(gray, cur_keypoints_, cur_descriptors_);
  OrbShift shift;
  if (has_previous_ && !prev_descriptors_.empty() && !cur_descriptors_.empty()) {
    // Thesis Fig. A.3 matches current (query) against previous (train); the
    // texture displacement previous -> current is cur.pt - prev.pt.
    matches_.clear();
    matcher_.match(cur_descriptors_, prev_descriptors_, matches_);
    // Keep the best good_match_fraction by Hamming distance (Fig. A.3).
    std::sort(matches_.begin(), matches_.end());
    const auto keep = static_cast<std::size_t>(static_cast<double>(matches_.size()) * config_.good_match_fraction);
    matches_.resize(std::min(matches_.size(), keep));
    std::vector<cv::Point2d> d;  // allocation: part of the OpenCV-bound baseline
    d.reserve(matches_.size());
    for (const cv::DMatch& m : matches_) {
      const cv::Point2f& cur = cur_keypoints_[static_cast<std::size_t>(m.queryIdx)].pt;
      const cv::Point2f& prev = prev_keypoints_[static_cast<std::size_t>(m.trainIdx)].pt;
      // KeyPoint.pt is (x = column, y = row); we keep (d_row, d_col).
      d.emplace_back(static_cast<double>(cur.y - prev.y), static_cast<double>(cur.x - prev.x));
    }
    shift = summarise_displacements(d, config_);
  }
  std::swap(prev_keypoints_, cur_keypoints_);
  std::swap(prev_descriptors_, cur_descriptors_);
  has_previous_ = true;
  return shift;
}

OrbShift OrbFrameDifference::measure(const cv::Mat& previous, const cv::Mat& current) {
  set_previous(previous);
  return measure_and_advance(current);
}

}  // namespace gvs::dsp::thesis
