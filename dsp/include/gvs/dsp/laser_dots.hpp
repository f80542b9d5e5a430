// Finding the laser dots in a frame (docs/estimator.md, "Height from the
// laser dots"): each dot is searched along its track (the image of its
// beam: wherever the ground is, the dot is on it), its centroid measured to
// a fraction of a pixel, triangulated, and three dots give the ground plane
// (gvs/dsp/ground_plane.hpp). A dot that is not clearly there (off the
// frame, under dirt, on a dark patch) is not found; one with a rival as
// bright is found only if just one of the two makes a plausible ground
// plane with the other dots. Three points always make a plane, so with
// three dots a bright grain taken for a dot whose plane is still plausible
// gives a wrong height (docs/estimator.md, "Wrong dots"); a fourth beam
// checks the plane (the four must agree) and stands in for a dot not found,
// and where no plane of the brightest spots holds, or one of three only, a
// plane of three is checked by a fourth dot found where they put it, not the
// track's brightest (a three-dot plane's pitch and roll go out each only
// where the dots' usual scatter moves it little: without dot 0 or 1 the
// roll and not the pitch; no plane of three
// goes out whose fourth dot shows a few pixels beside where it puts it);
// failing that (a standing car over grains as bright as a dot), the four
// dots are looked for where they brightened since the last frame, moved
// together by the body's heave from where the last plane put them (three
// of them, where the fourth lies on a stone too dark to show it), and then
// against the last plane's frame scaled by the heave.
//
// Pure: no I/O, threads or clocks; every buffer is made in the constructor.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include <opencv2/core/mat.hpp>

#include "gvs/core/frame.hpp"
#include "gvs/core/laser_geometry.hpp"
#include "gvs/core/ride_height.hpp"

namespace gvs::dsp {

/// Why a dot was not found (or `found`).
enum class DotStatus : std::uint8_t { found, faint, contested, off_track, at_edge, no_track, off_plane };

/// A measured position of a dot (or of a rival as bright).
struct Candidate {
  double row = 0.0;
  double col = 0.0;
  core::Vec3 ground_mm;  ///< triangulated point, head axes
};

struct LaserDot {
  bool found = false;
  DotStatus status = DotStatus::no_track;
  double peak_sigmas = 0.0;     ///< response over the track's robust sigma
  double rival_fraction = 0.0;  ///< best rival's response over the peak's
  double row = 0.0;  ///< centroid, px
  double col = 0.0;
  double contrast_dn = 0.0;  ///< the dot's brightness over the ground beside it
  core::Vec3 ground_mm;      ///< triangulated point, head axes
  /// A candidate to mask (the dot, or a rival as bright): position and background.
  bool masked = false;
  double mask_row = 0.0, mask_col = 0.0, mask_background_dn = 0.0;
  bool rival = false;
  double rival_row = 0.0, rival_col = 0.0, rival_background_dn = 0.0;
  /// Contested: the best and its rival, both measured (the plane decides).
  std::array<Candidate, 2> candidates{};
  std::size_t alternatives = 0;

  /// The dot is `c`: found there.
  void take(const Candidate& c) {
    found = true;
    status = DotStatus::found;
    row = c.row;
    col = c.col;
    ground_mm = c.ground_mm;
  }
};

struct LaserDotResult {
  std::array<LaserDot, core::LaserGeometry::kMaxBeams> dots{};
  std::size_t found = 0;
  /// has_height / has_pitch / has_roll only with a plausible plane of at
  /// least three dots; four that disagree by enough to hide a wrong tilt
  /// keep the height only, three keep each angle their layout fixes.
  core::RideHeight ride;
};

class LaserDotFinder {
 public:
  /// Throws std::invalid_argument naming what is wrong (no beams, a beam
  /// whose track is not in the frame, heights out of order).
  LaserDotFinder(const core::CameraGeometry& camera, double nominal_height_mm, const core::LaserGeometry& lasers);

  /// Finds the dots in `gray` (CV_8UC1 of the camera's size). No allocation.
  /// Each frame on its own: no step 5.
  LaserDotResult find(const cv::Mat& gray);
  /// The same for a frame of a sequence taken at `t_ns` (the middle of its
  /// light, which lasts `exposure_us` from first to last): where no plane
  /// holds, step 5 looks for the dots near the last plane found within
  /// Thresholds::max_prior_age_s; each plane found is kept for the next
  /// frames. forget() drops it (a gap, a reset).
  LaserDotResult find(const cv::Mat& gray, std::int64_t t_ns, double exposure_us);
  void forget() { has_prior_ = has_last_responses_ = has_reference_ = false; }
  /// Blends the dots (and bright rivals on their tracks) of `result` into the
  /// ground beside them, in place, so that the velocity estimators do not
  /// see spots that move with the height instead of the ground.
  void mask(const LaserDotResult& result, cv::Mat& gray) const;

  /// What dsp::FrameProcessor does with each frame: `gray` copied into
  /// `masked` (allocated only when its size or type differ), the dots found
  /// in the copy and masked there. Each frame on its own, or of a sequence
  /// (t_ns, exposure_us as find()'s).
  LaserDotResult find_and_mask(const cv::Mat& gray, cv::Mat& masked) {
    gray.copyTo(masked);
    LaserDotResult found = find(masked);
    mask(found, masked);
    return found;
  }
  LaserDotResult find_and_mask(const cv::Mat& gray, cv::Mat& masked, std::int64_t t_ns, double exposure_us) {
    gray.copyTo(masked);
    LaserDotResult found = find(masked, t_ns, exposure_us);
    mask(found, masked);
    return found;
  }

  [[nodiscard]] const core::LaserGeometry& lasers() const { return lasers_; }

  /// When a dot counts as found, and which ground counts as the ground.
  struct Thresholds {
    /// Its response stands this many robust sigmas (1.4826 MAD of the
    /// responses along the track) above the track ...
    double min_sigmas = 4.0;
    /// The fourth dot looked for where three put it (step 4) needs only
    /// this many where the three are dots step 2 found: within 5 samples of
    /// a known place, not anywhere along a track of hundreds, the same
    /// chance of a noise peak passing asks about one sigma less (Gaussian
    /// tails: 4 sigma over 350 samples and 2.9 over 5 both pass about 1 %
    /// of tracks without a dot).
    double min_sigmas_where_put = 3.0;
    /// ... and at least this bright over the ground around it, DN ...
    double min_contrast_dn = 12.0;
    /// ... and no rival elsewhere on the track reaches this fraction of it.
    double max_rival_fraction = 0.75;
    /// A centroid further than this from the track is not the dot, px.
    double max_off_track_px = 1.5;
    /// A plane tilted more than this is not the ground (a wrong dot), deg:
    /// a Formula Student car pitches and rolls by up to about 2 deg. The
    /// tilt in any direction (the magnitude of pitch and roll together: the
    /// ground does not tilt further diagonally than along an axis).
    double max_tilt_deg = 3.0;
    /// Four dots agree on one plane when none is further from their
    /// least-squares plane than this, mm: 5 times the scatter of four good
    /// dots (about 0.02 mm on the procedural asphalt). With the design's
    /// symmetric dots each residual is a quarter of one dot's error, so a
    /// dot 0.4 mm off its ground (4 px along its track) is caught.
    double max_plane_residual_mm = 0.1;
    /// A plane of four dots goes out with its tilt only when no one dot
    /// wrong by what their disagreement allows could have tilted it by more
    /// than this, deg (tilt_doubt_deg in ground_plane.hpp: 8.2 deg per mm
    /// of residual for the design, so 0.06 mm); past it the height stays
    /// (one dot moves it by a quarter of its error) and the tilt does not.
    double max_tilt_doubt_deg = 0.5;
    /// A plane of three dots (nothing checks it) goes out with its pitch, and
    /// with its roll, only when the dots' usual scatter, dot_scatter_mm each
    /// (the asphalt's reflectance under the spot: the procedural asphalt's
    /// 0.034 mm, the roughest seen), moves that angle by at most this RMS,
    /// deg (tilt_sigma_deg in ground_plane.hpp), so that max_tilt_doubt_deg
    /// is 3.3 of its sigmas away. Without dot 2 or 3: pitch 0.10, roll 0.12
    /// deg; without dot 0 or 1: pitch 0.17 (over one dot's 14 mm), which
    /// goes out without it, roll 0.07. (Four: 0.10 and 0.07.)
    double max_tilt_sigma_deg = 0.15;
    double dot_scatter_mm = 0.034;
    /// Step 5: how fast the camera's height may change, mm/s: a kerb strike
    /// lifts it by about 10 mm in 50 ms (200 mm/s on average, some 300 at
    /// its fastest); the dots are looked for within what this allows since
    /// the last plane, plus prior_margin_mm for the tilt's change.
    double max_height_rate_mm_per_s = 400.0;
    double prior_margin_mm = 0.5;
    /// A plane older than this is no guide, s (six frames at 60 fps).
    double max_prior_age_s = 0.1;
    /// Step 5 takes no dot smeared along its track by more than this many
    /// spot sigmas: the height changing fast within the exposure (a kerb
    /// strike under 3 ms of light: 6 px) moves its centroid off the middle
    /// of the light by an unknown share. Any other plane whose dots ran that
    /// far keeps its height and not its tilt (a double pulse 6.6 ms long at
    /// 60 mm/s of heave images each dot twice, 4 px apart, and the centroid
    /// settles on either).
    double max_smear_sigmas = 2.0;
  };
  [[nodiscard]] const Thresholds& thresholds() const { return thresholds_; }
  void set_thresholds(const Thresholds& t) { thresholds_ = t; }

 private:
  struct Offset {
    int dr, dc;
    double along, across;  ///< in units of the spot's sigmas
  };
  struct Track {
    std::vector<double> row, col;  ///< sample positions, 1 px apart, window inside the frame
    double row0 = 0.0, col0 = 0.0;  ///< the line: (row0, col0) + u (er, ec)
    double er = 1.0, ec = 0.0;
    double sigma_along_px = 1.0, sigma_across_px = 1.0;
    double px_per_mm_height = 10.0;  ///< along the track, per mm of level ground's height
    /// Every pixel the responses along the track read: per row, first and last column.
    struct RowSpan {
      int row, first_col, last_col;
    };
    std::vector<RowSpan> pixels;
    std::vector<Offset> inner, side, window;  ///< the spot, the ring around it, the centroid's window
    /// The spot and its ring moved by one pixel (dr, dc in -1..1, index
    /// 3 (dr + 1) + dc + 1): the pixels that enter and leave each, from the
    /// old position. Consecutive samples are at most one pixel apart, so
    /// step 1 updates the sums instead of adding the whole spot again.
    struct Step {
      std::vector<Offset> inner_in, inner_out, side_in, side_out;
    };
    std::array<Step, 9> steps;
    /// Where pixel (pixel_row, pixel_col) lies along the track, in samples (1 px apart).
    [[nodiscard]] double along_px(double pixel_row, double pixel_col) const {
      return (pixel_row - row[0]) * er + (pixel_col - col[0]) * ec;
    }
  };
  /// Steps 1-4 on this frame alone.
  LaserDotResult detect(const cv::Mat& gray);
  /// Drops the tilt of a four-dot plane past Thresholds::max_tilt_doubt_deg,
  /// or the pitch or roll of a three-dot plane past Thresholds::max_tilt_sigma_deg.
  void withhold_doubtful_tilt(LaserDotResult& out) const;
  /// Whether a dot that ran `run_px` along track `t` within the light is
  /// smeared: more than Thresholds::max_smear_sigmas of its spot.
  [[nodiscard]] bool smeared(const Track& t, double run_px) const {
    return run_px > thresholds_.max_smear_sigmas * t.sigma_along_px;
  }
  /// Whether a found dot ran more than Thresholds::max_smear_sigmas along
  /// its track within the light, at its rate since the last plane (`age_s` ago).
  [[nodiscard]] bool smeared_dots(const LaserDotResult& out, double age_s, double exposure_us) const;
  void find_one(const cv::Mat& gray, std::size_t k, LaserDot& dot);
  DotStatus measure(const cv::Mat& gray, std::size_t k, std::size_t sample, Candidate& out) const;
  void resolve(const cv::Mat& gray, LaserDotResult& out) const;
  /// Where beam k meets the plane through p1, p2, p3: px along its track.
  /// False when it does not meet it below the head.
  bool along_where_plane_meets(std::size_t k, const core::Vec3& p1, const core::Vec3& p2, const core::Vec3& p3,
                               double& along_px) const;
  /// Step 2's bars on track k's response at `sample` (contrast and robust
  /// sigmas), without the rival rule.
  [[nodiscard]] bool stands_out(std::size_t k, std::size_t sample) const {
    return stands_out(k, sample, thresholds_.min_sigmas);
  }
  [[nodiscard]] bool stands_out(std::size_t k, std::size_t sample, double min_sigmas) const {
    const double response = responses_[k][sample];
    return response >= thresholds_.min_contrast_dn && response - median_[k] >= min_sigmas * spread_[k];
  }
  void fourth_where_three_put_it(const cv::Mat& gray, LaserDotResult& out) const;
  /// With three dots of four found: whether the fourth beam's track shows a
  /// dot (step 2's bars) a few pixels beside where their plane puts it, and
  /// brighter than there: the plane is off (one of the three a grain).
  [[nodiscard]] bool fourth_beside_where_three_put_it(const LaserDotResult& out) const;
  /// Step 1 on track k of `gray`: the centre-surround response and the
  /// ground around it at each sample.
  void track_responses(const cv::Mat& gray, std::size_t k, std::vector<double>& resp, std::vector<double>& bgs) const;
  /// Step 5's plane: none; four or three dots against the last frame;
  /// dots against the last plane's frame scaled by the height change.
  enum class Brightened : std::uint8_t { none, four, three, scaled };
  Brightened near_the_last_plane(const cv::Mat& gray, double age_s, double exposure_us, LaserDotResult& out);
  /// The height change since the last plane that lines up the four
  /// brightenings best: the first of the best (where the dots are taken)
  /// and the middle of their run (the scale of the image).
  struct HeightChange {
    double dh_mm = 0.0, scale_dh_mm = 0.0;
  };
  /// Step 5 on brightening_: its median and spread per track, and the height
  /// change (false: the dots ran too far along their tracks within the
  /// light at that rate).
  bool brightened_height_change(double age_s, double exposure_us, double reach_mm, HeightChange& change);
  /// Step 5: the most brightened sample within kSideSamples of `along` on track k.
  double brightening_near(std::size_t k, double along, std::size_t& sample) const;
  /// Step 5: the plane of the dots newly there where the height change puts
  /// them (four, or three and the fourth on a dark stone); 0, 3 or 4.
  std::size_t plane_where_brightened(const cv::Mat& gray, double dh_mm, LaserDotResult& out);
  /// rescaled_: the last plane's frame as the camera sees it from `height_now_mm`.
  void rescale_reference(double height_now_mm);
  /// Step 5: whether track k at `sample` is a dot newly there: step 2's
  /// contrast, and its brightening standing out by step 2's sigmas (of the
  /// track's brightenings: `median`, `spread`).
  [[nodiscard]] bool newly_there(std::size_t k, std::size_t sample, double median, double spread) const {
    return responses_[k][sample] >= thresholds_.min_contrast_dn &&
           brightening_[k][sample] - median >= thresholds_.min_sigmas * spread;
  }
  /// Step 5: whether track k shows a dot newly there 3-15 samples beside `along`.
  [[nodiscard]] bool brightened_beside(std::size_t k, double along, double median, double spread) const;
  /// Median and 1.4826 MAD of values[0 .. n) (scratch_ is overwritten).
  void robust_spread(const std::vector<double>& values, std::size_t n, double& median, double& spread);
  void remember_plane(const cv::Mat& gray, const LaserDotResult& out, std::int64_t t_ns);
  /// Dot k is `c`, measured at `sample` of its track: found and masked
  /// there. What step 2 masked elsewhere on the track (a grain taken for the
  /// dot) stays masked, as the rival, where that slot is free or holds the dot.
  void take_at(std::size_t k, std::size_t sample, const Candidate& c, LaserDot& d) const;
  [[nodiscard]] bool plausible(const core::RideHeight& ride) const;

  core::CameraGeometry camera_;
  double nominal_height_mm_;
  core::LaserGeometry lasers_;
  std::array<Track, core::LaserGeometry::kMaxBeams> tracks_{};
  /// Per track: the centre-surround response and the ground around each sample, their median and robust spread.
  std::array<std::vector<double>, core::LaserGeometry::kMaxBeams> responses_, backgrounds_;
  std::array<double, core::LaserGeometry::kMaxBeams> median_{}, spread_{};
  std::vector<double> scratch_;
  Thresholds thresholds_;
  /// Step 5's guide: where the last plane put each dot (px along its track) and when.
  bool has_prior_ = false;
  std::array<double, core::LaserGeometry::kMaxBeams> prior_along_px_{};
  std::int64_t prior_t_ns_ = 0;
  /// The responses along each track in the last frame of the sequence.
  bool has_last_responses_ = false;
  std::int64_t last_responses_t_ns_ = 0;
  std::array<std::vector<double>, core::LaserGeometry::kMaxBeams> last_responses_, brightening_;
  std::array<double, core::LaserGeometry::kMaxBeams> brightening_median_{}, brightening_spread_{};
  /// The last plane's frame and height: a standing car's ground as it was,
  /// which scaled by the height's change shows the grains where they are now.
  bool has_reference_ = false;
  double reference_height_mm_ = 0.0;
  cv::Mat reference_gray_, rescaled_;
  std::array<std::vector<double>, core::LaserGeometry::kMaxBeams> reference_responses_;
  std::vector<double> scratch_backgrounds_;
};

}  // namespace gvs::dsp
