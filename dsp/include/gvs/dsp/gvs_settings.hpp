// The "gvs" estimator's settings: every threshold the analyses and the
// tracking rules use, with what it was chosen on (docs/estimator.md).
#pragma once

#include "gvs/dsp/frame_check.hpp"

namespace gvs::dsp {

struct GvsEstimatorSettings {
  FrameCheckLimits frame_check;
  // Standstill: mean squared frame difference over twice the frame variance.
  double still_ratio = 0.12;
  /// ... and the frame must hold texture, not only the sensor's fixed
  /// pattern: neighbouring pixels correlated at least this much (check_still).
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
  /// A half's correlation peak lies within about this many px over its
  /// peak-to-RMS of the true shift (fitted on 3700 pairs of `crawl` and
  /// `stop` over the five photographs, two fainter copies and the
  /// procedural ground: error over this model 0.5-0.9 RMS, 1.3 on the
  /// faintest). The yaw rate's standard error follows from it.
  double pair_peak_scatter_px = 4.0;
  /// A pair gives its yaw rate only if that standard error is at most this:
  /// the two halves' shifts along a 15-30 px streak on faint ground scatter
  /// by a few pixels, a yaw rate tens of deg/s off.
  double pair_max_yaw_rate_sigma_dps = 3.0;
  /// Dark pairs (mean grey below unlearnt_max_mean_grey): both frames'
  /// halves are taken without the sensor's pixel pattern once it is learnt
  /// from this many frames. The pattern is the same in both frames and,
  /// under-exposed, 10x the temporal noise: it outweighed the streaked
  /// texture in most bins, and from ~2 km/h (20 px streaks) the pair fell
  /// below pair_min_quality. From 2 frames learnt, the pattern still held
  /// those frames' texture (`accel` under: one pair 5.5 % slow at quality 1).
  int pair_pixel_pattern_min_frames = 10;
  double max_accel_mps2 = 20.0;      ///< clamp of the half-frame lag compensation
  /// A single frame without a speed whose streak is not too long (blur-*)
  /// tries the pair. With a clearly elongated spectrum (anisotropy >= 0.8:
  /// a streak of 10 px or more; docs/estimator.md, "Short streaks, faint
  /// streaks") the pair is taken only if its velocity makes a streak of at
  /// least this length in this frame: a shorter one means frames that do not
  /// overlap matched by chance. On ground with a grain of its own (the tiled
  /// photograph torcs_etrack2) a 15 px streak reads anisotropy >= 0.8 and an
  /// axis 1-2 deg off, while the pair of the same frames is within 0.2 deg.
  double pair_min_streak_px_elongated = 8.0;
  // Single-frame blur.
  /// Below: the streak is too short to carry a direction ("short-streak",
  /// quality 0). On asphalt at 0.1 mm/px the spectrum reaches 0.6 at a
  /// ~15 px streak; below it the direction error grows past 2-20 deg
  /// (docs/estimator.md, "Short streaks").
  double min_anisotropy = 0.6;
  double min_texture_snr = 0.3;      ///< band power above the noise floor over the noise: below, "no-texture"
  /// ... unless the frame is well lit, the sensor's pixel pattern is out of
  /// its spectrum, and the refined spectral line alone holds this much
  /// texture over the noise (BlurAnalyzer::line_snr): a streak longer than
  /// the frame on fine ground (3 ms at 60-140 km/h on the photographs: band
  /// SNR 0.1-0.3, line 2.1-8, direction within 0.19 deg). Ground of 2 grey
  /// levels, where medium streaks read 1-2 deg off, stays below 1.2; the
  /// sensor's pattern and noise alone below 0.02 (docs/estimator.md,
  /// "Streaks longer than the frame").
  double min_line_snr = 2.0;
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
  /// Quality factor, at the least, of a well-lit frame's texture SNR where
  /// its streak end gave the speed. The (SNR / 10)^2 law was measured on
  /// dark frames, where the sensor's column pattern pulls the spectrum's
  /// axis; a well-lit frame whose streak end stands clear has its axis from
  /// that end's lag (up to 100 px) or from the refined spectral line along
  /// it. Such frames at texture SNR 4-10: 0.11 deg RMS, max 0.87, speed
  /// 0.38 % RMS, max 2.4 % (1348 frames of 78 seed-1 3 ms replays;
  /// docs/estimator.md, "Short streaks, faint streaks").
  double lit_speed_snr_quality = 0.45;
  double dark_max_streak_px = 100.0;  ///< dark frames: longer streaks give no speed (their end is found short)
  double good_texture_snr = 10.0;    ///< full quality from here (normal light: 10-70)
  double refine_min_anisotropy = 0.8; ///< longer streaks: refine the axis on the spectral line
  /// How far an axis not refined may be off: the ground's own grain tilts a
  /// weakly elongated spectrum (3 deg on acg_Asphalt025C at 60 px streaks,
  /// anisotropy 0.76-0.79), and the streak end is then looked for across
  /// the ray too (BlurAnalyzer::streak_length's axis_tan).
  double unrefined_axis_error_deg = 5.0;
  /// A clear streak end from this length gives the axis (its lag's direction),
  /// even where it is too short for a speed (below min_streak_px, or
  /// min_streak_px_cold without a recent speed): on the thesis's 20 px frames
  /// the end is within 0.5 deg, the spectrum's orientation 1.0-1.5 deg off
  /// (docs/accuracy.md, "The thesis's own frames").
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
  /// An older speed, up to this age, still bounds the streak for re-acquiring
  /// it (StreakSearch::reacquire): by max_accel_mps2 times its age.
  double reacquire_memory_s = 0.5;
  double max_streak_background = 0.07;          ///< typical |A| off the streak end over A(0), no recent speed
  double max_streak_background_tracked = 0.13;  ///< ... searching around a recent speed (narrow window)
  /// A tracked end under the gates above still counts down to these where
  /// the power cepstrum stands witness (its end within
  /// cepstrum_max_disagreement, at min_streak_significance or more).
  double min_streak_significance_witnessed = 2.5;
  double max_streak_background_witnessed = 0.2;
  /// Texture power over noise needed for a speed from a streak: below ~4
  /// (under-exposed long streaks) the streak end is found 10-60 % short.
  double min_speed_texture_snr = 4.0;
  /// ... on a well-lit frame (VelocityEstimate::well_lit()), whose streak
  /// end then counts only when the power cepstrum's end
  /// (BlurAnalyzer::streak_length_cepstral) lies within
  /// cepstrum_max_disagreement of it. The adaptive strobe holds
  /// ph_asphalt_04's streaks at SNR 1.2-2; below ~1 are frames whose streak
  /// outgrew the exposure. Without the cepstrum, tracked ends of significance
  /// 3.5-4 at SNR 2.5-3 locked onto a fixed 151 px lag of a tiled texture
  /// (21 % long), and one of significance 6.8 at SNR 1.8 read 5.5 % long.
  double min_speed_texture_snr_lit = 1.0;
  /// How far apart (a fraction of the length) the cepstrum's end and the
  /// streak end may lie for a faint end on a well-lit frame, or a well-lit
  /// frame's end beyond dark_max_streak_px, to count; the length is then
  /// their mean. (2 % kept 3-5 % fewer of ph_asphalt_04's adaptive frames
  /// at the same RMS.)
  double cepstrum_max_disagreement = 0.03;
  /// ... for a streak end found around a recent speed, whose window has
  /// already narrowed the search: on tracked ends of 70 replays (every
  /// ground and exposure mode) the cepstrum's end was the closer reading, and
  /// where the two lay 3-5 % apart their mean was within 2.9 % of the truth
  /// (41 ends; 6-8 % apart, up to 6.9 %). Choosing between rival ends still
  /// takes cepstrum_max_disagreement.
  double cepstrum_max_disagreement_tracked = 0.05;
  double max_streak_fraction = 0.42; ///< longest measurable streak / frame extent along it
  /// The power cepstrum looks for the streak end up to this fraction of the
  /// frame extent, beyond max_streak_fraction (it divides out no window
  /// overlap): a streak that outgrew the window shows there, deeper than a
  /// trough of the grain inside it (torcs_wheel1 `accel` seed 3 frame 133:
  /// 168 px for 170 px, where both readings inside the window say 137 px).
  /// Beyond half the frame the circular surface puts the streak's alias
  /// (extent - L) nearer than the streak.
  double cepstrum_max_streak_fraction = 0.5;
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

}  // namespace gvs::dsp
