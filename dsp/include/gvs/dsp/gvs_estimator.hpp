// The product estimator, method "gvs": picks per frame the measurement the
// physics allows (docs/estimator.md).
//
//   still       consecutive frames identical up to noise: speed 0
//   pair        consecutive frames overlap (slow): phase correlation of two
//               half-frame windows -> shift (velocity, sign included) and the
//               difference of their shifts -> yaw rate
//   blur-*      one frame: streak axis (power spectrum orientation) and, when
//               the streak fits in the frame, its length (derivative
//               autocorrelation) -> direction up to sign, and speed
//   streak-*    as blur-*, but the streak is too long to measure: direction only
//   short-streak one frame whose streak is too short to carry a direction
//               (quality 0; the exposure controller lengthens the exposure)
//   dpiv-*      double-pulse frame: displacement between the two images
//               (autocorrelation side peak) -> velocity up to sign
// The suffix says what decided the sign: -cont (continuity with the previous
// estimate), -energy (unequal pulse energies), -fwd (no history: forward assumed).
#pragma once

#include <memory>
#include <vector>

#include <opencv2/core/mat.hpp>

#include "gvs/dsp/blur_analysis.hpp"
#include "gvs/dsp/estimator.hpp"
#include "gvs/dsp/fine_texture.hpp"
#include "gvs/dsp/frame_check.hpp"
#include "gvs/dsp/geometry.hpp"
#include "gvs/dsp/phase_correlation.hpp"
#include "gvs/dsp/spectrum.hpp"

namespace gvs::dsp {

struct GvsEstimatorSettings {
  FrameCheckLimits frame_check;
  // Standstill: mean squared frame difference over twice the frame variance.
  double still_ratio = 0.12;
  /// ... and the frame must hold texture, not only the sensor's fixed
  /// pattern: neighbouring pixels correlated at least this much (is_still).
  double still_min_neighbour_corr = 0.3;
  /// ... and both frames must be sharp (measure_fine_texture): fine texture
  /// along the weakest direction at least this fraction of the strongest
  /// (sharp photographed ground 0.71-0.87; a 40 px streak along a row 0.05,
  /// along a diagonal 0.3; docs/estimator.md, "Standstill needs sharp ground")
  double still_min_isotropy = 0.5;
  /// ... and the smallest of the four directional texture powers at least
  /// this fraction of the largest (sharp photographed ground 0.50-0.72; a
  /// diagonal streak of 75-90 px on a fine grain 0.06-0.33, where the
  /// isotropy above still read 0.47-0.55)
  double still_min_step_ratio = 0.35;
  /// ... and at least this fraction of the lag-1 difference power (sharp
  /// photographed ground 2.0-2.4; under-exposed procedural ground stays
  /// above it, its `stop` runs read `still` on every standing frame; the
  /// sensor's pattern alone ~0)
  double still_min_fine_texture = 0.1;
  // Pair <-> single-frame switching on the expected shift between frames (px),
  // with hysteresis: leave pair mode above the first, come back below the second.
  double pair_leave_shift_px = 185.0;
  double pair_enter_shift_px = 150.0;
  double pair_max_shift_px = 200.0;
  double pair_exclude_px = 3.0;      ///< fixed-pattern noise peak at lag 0 (and its spread)
  double pair_min_peak_to_rms = 7.0; ///< below: no match
  double pair_min_quality = 0.3;     ///< below: the pair is not used
  /// Dark pairs (mean grey below unlearnt_max_mean_grey): both frames'
  /// halves are taken without the sensor's pixel pattern once it is learnt
  /// from this many frames. The pattern is the same in both frames and,
  /// under-exposed, 10x the temporal noise: it outweighed the streaked
  /// texture in most bins, and from ~2 km/h (20 px streaks) the pair fell
  /// below pair_min_quality. From 2 frames learnt, the pattern still held
  /// those frames' texture (`accel` under: one pair 5.5 % slow at quality 1).
  int pair_pixel_pattern_min_frames = 10;
  double max_accel_mps2 = 20.0;      ///< clamp of the half-frame lag compensation
  // Single-frame blur.
  /// Below: the streak is too short to carry a direction ("short-streak",
  /// quality 0). On asphalt at 0.1 mm/px the spectrum reaches 0.6 at a
  /// ~15 px streak; below it the direction error grows past 2-20 deg
  /// (docs/estimator.md, "Short streaks").
  double min_anisotropy = 0.6;
  double min_texture_snr = 0.3;      ///< band power above the noise floor over the noise: below, "no-texture"
  /// Dark frames: below this texture SNR (with the column pattern taken
  /// out), the spectrum is taken again with the sensor's whole fixed pattern
  /// taken out (learnt per pixel from frames of moving ground), and the
  /// axis weighted by ring_gain(). Under-exposed (mean grey ~10) with 3 ms:
  /// the pixels' own offsets (DSNU, 1.5 grey levels RMS) are 10x the noise
  /// left, and above ~15 km/h the streaks average the texture down to well
  /// below them (docs/estimator.md, "Dark frames").
  double pixel_pattern_max_texture_snr = 4.0;
  int pixel_pattern_min_frames = 2;   ///< learnt from at least this many frames before it is used
  /// A dark frame (mean grey below unlearnt_max_mean_grey) after a dark one
  /// takes its spectrum without the pixel pattern straight away (one DFT
  /// less); from this texture SNR (pattern out) it is taken again as for a
  /// bright frame. Under-exposed with 3 ms the pattern out multiplies the
  /// SNR by ~8, so this is about pixel_pattern_max_texture_snr.
  double pixel_pattern_exit_texture_snr = 32.0;
  double pixel_pattern_min_shift_px = 20.0;  ///< learnt from frames whose ground moved this far since the last
  /// Before any pattern is learnt, a frame darker than this (mean grey) with
  /// a texture SNR below good_texture_snr gives no direction: the column
  /// pattern (~0.5 grey levels) may be most of what it shows. Below it a
  /// frame also counts as dark for pairs (pair_pixel_pattern_min_frames)
  /// and for the straight-to-pattern-out spectrum (pixel_pattern_exit_texture_snr).
  double unlearnt_max_mean_grey = 30.0;
  /// Quality factor of a dark frame (pixel pattern taken out): below 0.5, but
  /// not below the exposure controller's 0.3 where the rest is good.
  double dark_frame_quality = 0.45;
  double dark_max_streak_px = 100.0;  ///< dark frames: longer streaks give no speed (their end is found short)
  double good_texture_snr = 10.0;    ///< full quality from here (normal light: 10-70)
  double refine_min_anisotropy = 0.8; ///< longer streaks: refine the axis on the spectral line
  /// A clear streak end from this length gives the axis (its lag's direction),
  /// even where it is too short for a speed (below min_streak_px, or
  /// min_streak_px_cold without a recent speed): on the thesis's 20 px frames
  /// the end is within 0.5 deg, the spectrum's orientation 1.4 deg off.
  double axis_from_streak_end_px = 18.0;
  /// ... up to this length: longer streaks give a sharper line in the
  /// spectrum (refined, weighted to high |k|: ~0.03 deg RMS against ~0.1 from
  /// the end's lag at 125-210 px; docs/estimator.md).
  double axis_from_streak_end_max_px = 100.0;
  double long_streak_anisotropy = 0.96;///< no speed and above: "streak-*" (too long), else "blur-*"
  double refine_sigma = 0.05;        ///< rad/px, half-width of the line used
  /// From this texture SNR the line is weighted towards high |k| (refine_axis's high_k_weight).
  double refine_high_k_min_texture_snr = 4.0;
  double min_streak_search_px = 16.0; ///< the streak-end search starts here
  double min_streak_px = 20.0;       ///< shorter streaks: length not measured (texture grain biases it)
  double min_streak_px_cold = 30.0;  ///< ... without a recent speed
  /// Streak-end search window around a recent speed: +-this fraction, plus
  /// max_accel_mps2 times the speed's age.
  double speed_window_fraction = 0.15;
  double speed_memory_s = 0.055;     ///< a speed this recent is "recent": 3 frames at 60 fps (by time: frames may be skipped)
  double max_streak_background = 0.07;          ///< typical |A| off the streak end over A(0), no recent speed
  double max_streak_background_tracked = 0.13;  ///< ... searching around a recent speed (narrow window)
  /// Texture power over noise needed for a speed from a streak: below ~4
  /// (under-exposed long streaks) the streak end is found 10-60 % short.
  double min_speed_texture_snr = 4.0;
  double max_streak_fraction = 0.42; ///< longest measurable streak / frame extent along it
  double min_streak_depth = 0.06;
  double min_streak_significance = 3.5;       ///< streak end over the ray's RMS
  double min_streak_significance_cold = 6.0;  ///< without a previous speed to check against
  // Double pulse.
  double min_double_height = 0.05;
  double max_double_second = 0.8;
  double min_energy_confidence = 0.15;  ///< |asymmetry| needed to use it for the sign
  double good_double_texture_snr = 2.0;  ///< full quality from here; below, quality ~ SNR
  // Sign continuity: the previous direction is trusted this long.
  double continuity_max_age_s = 0.5;
};

class GvsEstimator final : public VelocityEstimator {
 public:
  explicit GvsEstimator(const EstimatorConfig& config, const GvsEstimatorSettings& settings = {});
  ~GvsEstimator() override;

  VelocityEstimate estimate(const FrameView& frame) override;
  void reset() override;

 private:
  enum class Mode { pair, single };
  enum class SignSource { continuity, energy, forward };

  VelocityEstimate estimate_pair(const FrameView& frame, std::int64_t t_mid_ns, double dt_s);
  VelocityEstimate estimate_single(const FrameView& frame, std::int64_t t_mid_ns);
  VelocityEstimate estimate_double(const FrameView& frame, std::int64_t t_mid_ns);
  void update_mode(double dt_s);
  void learn_column_pattern(const cv::Mat& gray, double mean_grey);
  [[nodiscard]] const float* column_pattern() const;
  void learn_pixel_pattern(const cv::Mat& gray, double mean_grey);
  /// Takes the windowed spectrum of `gray` into `spectrum` through `with`,
  /// without the pixel pattern (pixel_pattern_in_use_) or the column pattern.
  void take_spectrum(WindowedSpectrum& with, const cv::Mat& gray, cv::Mat& spectrum);
  /// The pair's half-window spectra of `gray` into slot `slot`, without the
  /// pixel pattern if `pattern_out`.
  void take_halves(const cv::Mat& gray, int slot, bool pattern_out);
  bool is_still(const cv::Mat& gray, double& ratio) const;
  [[nodiscard]] bool ground_is_sharp(const FineTexture& texture) const;
  /// Chooses the sign (+1/-1) of a unit axis in vehicle axes: continuity with
  /// the previous direction, else the pulse-energy vote, else forwards.
  SignSource resolve_sign(Vec2 axis_vehicle, std::int64_t t_mid_ns, double energy_vote,
                          double& sign) const;
  void remember(const FrameView& frame, std::int64_t t_mid_ns, const VelocityEstimate& e);

  CameraGeometry cam_;
  GvsEstimatorSettings set_;
  cv::Size size_;
  cv::Rect left_;   ///< half windows for pair correlation and yaw
  cv::Rect right_;

  WindowedSpectrum full_spectrum_;
  WindowedSpectrum half_spectrum_;
  /// Hann-windowed (taper 1) spectrum, only to check a streak length found
  /// without a recent speed (see estimate_single: circular aliasing).
  WindowedSpectrum hann_spectrum_;
  PhaseCorrelator half_correlator_;
  BlurAnalyzer blur_;

  cv::Mat spec_full_;
  cv::Mat spec_hann_;
  cv::Mat spec_left_[2];
  cv::Mat spec_right_[2];
  int cur_ = 0;  ///< index of the current half spectra; 1 - cur_ holds the previous frame's
  bool prev_halves_valid_ = false;
  bool prev_halves_pattern_out_ = false;  ///< the previous frame's halves were taken without the pixel pattern
  bool halves_this_frame_ = false;
  double cur_mean_grey_ = 0.0;
  double last_axis_anisotropy_ = 1.0;  ///< of the last single-frame analysis
  // Column fixed-pattern noise, learnt while the texture changes completely
  // from frame to frame (fast: single-frame mode), so the texture averages out.
  std::vector<float> column_pattern_;
  std::vector<double> column_sum_;
  int column_frames_ = 0;
  // The sensor's whole fixed pattern, per pixel (offset from the frame's
  // mean, grey levels), learnt from frames of moving ground the same way;
  // used for dark frames only (pixel_pattern_max_texture_snr).
  cv::Mat pixel_pattern_;  ///< CV_32F
  int pixel_frames_ = 0;
  bool pixel_pattern_in_use_ = false;  ///< this frame's single-frame spectra are without it
  bool single_frame_tried_ = false;    ///< estimate_single() ran on this frame
  bool last_single_dark_ = false;      ///< the last single-frame analysis used the pixel pattern
  BlurAnalyzer::RingGain ring_gain_{};
  cv::Mat prev_gray_;
  bool prev_valid_ = false;
  bool prev_double_ = false;
  double prev_lit_us_ = 0.0;
  std::int64_t prev_t_mid_ns_ = 0;
  double prev_mean_grey_ = 0.0;

  Mode mode_ = Mode::pair;
  VelocityEstimate last_;            ///< previous output
  bool last_valid_ = false;
  std::int64_t last_direction_t_ns_ = 0;
  Vec2 last_direction_{1.0, 0.0};    ///< unit vector, vehicle axes
  bool has_last_direction_ = false;
  /// The last direction's sign was measured (pair, pulse energies, or
  /// continuity from a measured one), not assumed (forward prior).
  bool last_sign_known_ = false;
  bool sign_known_now_ = false;
  /// A streak too long to measure says the speed is at least half the
  /// longest measurable streak's (floor for a streak length found without a
  /// recent speed: a 500 px streak cannot become a 44 px one in one frame).
  bool has_speed_floor_ = false;
  double speed_floor_mps_ = 0.0;
  std::int64_t speed_floor_t_ns_ = 0;
  bool has_last_speed_ = false;       ///< last measured speed (streak-length gate)
  double last_speed_mps_ = 0.0;
  std::int64_t last_speed_index_ = 0;
  std::int64_t last_speed_t_ns_ = 0;
  Vec2 last_pair_v_{};               ///< previous raw pair velocity (lag compensation)
  bool last_pair_valid_ = false;
};

/// Fills direction (and vx, vy, speed when `with_speed`) from a vehicle-axes velocity.
void set_velocity(VelocityEstimate& e, Vec2 v, bool with_speed);

/// Factory entry for the "gvs" method.
std::unique_ptr<VelocityEstimator> make_gvs_estimator(const EstimatorConfig& config);

}  // namespace gvs::dsp
