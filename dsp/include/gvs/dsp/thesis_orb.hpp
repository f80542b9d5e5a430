// Thesis baseline, part 1: ORB frame difference (gvs-thesis-2022 sections 4.3
// and 5.1). Features of the previous and the current frame are matched; each
// match gives a displacement vector of the ground texture between the frames.
#pragma once

#include <cstddef>
#include <vector>

#include <opencv2/core/mat.hpp>
#include <opencv2/core/types.hpp>
#include <opencv2/features2d.hpp>

namespace gvs::dsp::thesis {

struct OrbConfig {
  int max_features = 500;  ///< cv::ORB nfeatures (thesis MAX_FEATURES; OpenCV's default)
  /// Thesis Fig. A.3 sorts the matches by Hamming distance and keeps the best
  /// GOOD_MATCH_PERCENT of them. The thesis does not print the value; 0.15 is
  /// the one of the OpenCV alignment example its listing follows.
  double good_match_fraction = 0.15;
  int min_matches = 4;  ///< fewer good matches: no measurement
  /// Matches at which quality saturates (quality = R * min(1, n / this)).
  int matches_for_full_quality = 30;
};

/// Texture displacement from the previous to the current frame, in pixels.
struct OrbShift {
  bool ok = false;
  int match_count = 0;
  /// Direction of the displacement in camera axes, atan2(d_col, d_row), from the
  /// wrap-safe mean of the per-match angles (thesis 4.3: "all angles are averaged").
  double angle_cam_deg = 0.0;
  /// RMS length of the per-match displacements, thesis eq. 5.2.
  double rms_px = 0.0;
  double d_row_px = 0.0;  ///< rms_px * cos(angle): texture motion along rows (towards the rear)
  double d_col_px = 0.0;  ///< rms_px * sin(angle): texture motion along columns (to the right)
  /// Mean resultant length of the per-match unit vectors, [0, 1]: 1 when all
  /// matches point the same way.
  double angle_consistency = 0.0;
  double quality = 0.0;  ///< [0, 1]
};

/// ORB on two frames, brute-force Hamming matching with cross-check, per-match
/// displacement vectors (thesis Fig. A.3). Keeps the features of the last
/// frame it saw so that a stream costs one detection per frame.
///
/// Allocation: cv::ORB and cv::BFMatcher allocate inside OpenCV on every call.
/// That is the thesis baseline and is left as it is (measured in thesis_bench).
class OrbFrameDifference {
 public:
  explicit OrbFrameDifference(const OrbConfig& config = {});

  /// Features of `gray` become the "previous" ones; no measurement.
  void set_previous(const cv::Mat& gray);
  /// Matches `gray` against the previous features, then makes `gray` the
  /// previous frame. Not ok without previous features or with too few matches.
  OrbShift measure_and_advance(const cv::Mat& gray);
  [[nodiscard]] bool has_previous() const { return has_previous_; }
  void reset() { has_previous_ = false; }

  /// One-shot form: texture displacement from `previous` to `current`.
  OrbShift measure(const cv::Mat& previous, const cv::Mat& current);

 private:
  void detect(const cv::Mat& gray, std::vector<cv::KeyPoint>& keypoints, cv::Mat& descriptors);

  OrbConfig config_;
  cv::Ptr<cv::ORB> orb_;
  cv::BFMatcher matcher_;
  std::vector<cv::KeyPoint> prev_keypoints_;
  std::vector<cv::KeyPoint> cur_keypoints_;
  cv::Mat prev_descriptors_;
  cv::Mat cur_descriptors_;
  std::vector<cv::DMatch> matches_;
  bool has_previous_ = false;
};

/// The per-match statistics of thesis 4.3 / eq. 5.2 for displacement vectors
/// (d_row, d_col) in pixels: wrap-safe mean angle and RMS length. Exposed for tests.
OrbShift summarise_displacements(const std::vector<cv::Point2d>& d_row_col, const OrbConfig& config);

}  // namespace gvs::dsp::thesis
