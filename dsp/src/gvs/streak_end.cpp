// The streak end of one blurred frame: where it is looked for, and whether
// it is clear enough for the axis and the speed (streak_end.hpp).
#include "streak_end.hpp"

#include <algorithm>
#include <cmath>

#include "gvs/dsp/vocabulary.hpp"

namespace gvs::dsp {

StreakSearch streak_search(const MotionMemory& m, std::int64_t index, std::int64_t t_mid_ns, double extent_px,
                           double t_s, double m_per_px, const GvsEstimatorSettings& set) {
  StreakSearch s;
  const double max_px = set.max_streak_fraction * extent_px;
  const double cepstrum_max_px = set.cepstrum_max_streak_fraction * extent_px;
  s.lo_px = set.min_streak_search_px;
  s.hi_px = max_px;
  s.cepstrum_hi_px = cepstrum_max_px;
  const std::int64_t age = index - m.speed_index;
  // Recent by time, not by frame count: gvsd skips frames when processing
  // falls behind, and a skipped frame does not make the speed less known.
  const double age_s = static_cast<double>(t_mid_ns - m.speed_t_ns) * 1e-9;
  // The lengths the last speed allows now: +-speed_window_fraction, and
  // what max_accel_mps2 can add or take off since.
  const double slack_mps = set.max_accel_mps2 * age_s;
  const double shortest_px =
      std::max(0.0, (1.0 - set.speed_window_fraction) * m.speed_mps - slack_mps) * t_s / m_per_px - 2.0;
  const double longest_px = ((1.0 + set.speed_window_fraction) * m.speed_mps + slack_mps) * t_s / m_per_px + 2.0;
  if (m.has_speed && age >= 1 && age_s <= set.speed_memory_s) {
    s.min_significance = set.min_streak_significance;
    s.min_length_px = set.min_streak_px;
    s.max_background = set.max_streak_background_tracked;
    s.lo_px = std::max(s.lo_px, shortest_px);
    s.hi_px = std::min(s.hi_px, longest_px);
    s.cepstrum_hi_px = std::min(cepstrum_max_px, longest_px);
    s.cepstrum_sees_all = longest_px <= cepstrum_max_px;
    s.expected_px = m.speed_mps * t_s / m_per_px;
    return s;
  }
  s.min_significance = set.min_streak_significance_cold;
  s.min_length_px = set.min_streak_px_cold;
  s.max_background = set.max_streak_background;
  // ... and not shorter than a recent too-long streak allows (less what
  // max_accel_mps2 can take off since): seen in `sine` seed 4, a texture
  // "streak end" at 44 px (1.5 m/s) between 500 px streaks (16.7 m/s).
  const double v_floor = speed_floor_now_mps(m, t_mid_ns, set);
  if (v_floor > 0.0) s.lo_px = std::max(s.lo_px, v_floor * t_s / m_per_px - 2.0);
  // An older speed still bounds the streak: where every length it allows
  // lies within the cepstrum's reach, the streak cannot have outgrown it.
  if (m.has_speed && age >= 1 && age_s <= set.reacquire_memory_s && longest_px <= cepstrum_max_px) {
    s.reacquire = true;
    s.reacquire_lo_px = shortest_px;
    s.reacquire_hi_px = longest_px;
  }
  return s;
}

namespace {

/// The surface is circular: a streak end at lag L' also shows at lag
/// (frame - L') along an axis parallel to the rows or columns. A streak
/// longer than we measure (here 0.58-0.9 of the frame) thus fakes a
/// shorter one, and the flat Tukey window keeps that alias strong
/// (overlap 0.33 at 0.6 of the frame; Hann 0.07). accel seed 9: 226 px
/// streaks read as 159 px, three frames at quality 0.7, 30 % slow.
/// Without a recent speed to vouch for it, the length must also be found
/// through a Hann window. Only where an alias can land on the axis (within
/// 3 px of it across the frame) and be strong (from streaks up to 0.85 of
/// the frame: here L > 0.15 of it); one more forward DFT on such frames.
/// False: the length may be such an alias.
bool not_an_alias(const cv::Mat& gray, const StreakAxis& axis, const StreakLength& len,
                  const StreakSearch& search, const SensorPattern& pattern, bool pattern_out,
                  double axis_tan, SpectrumWorkspace& ws) {
  const bool along_rows = std::abs(axis.u_col) * gray.rows < 3.0;
  const bool along_cols = std::abs(axis.u_row) * gray.cols < 3.0;
  const double alias_min_px = 0.15 * (along_rows ? gray.rows : gray.cols);
  if (!(along_rows || along_cols) || len.length_px <= alias_min_px) return true;
  take_spectrum(ws.hann, gray, ws.hann_spectrum, pattern, pattern_out);
  const StreakLength check = ws.blur.streak_length(ws.hann_spectrum, axis, search.lo_px, search.hi_px, 0.0, axis_tan);
  // (Its sub-pixel fit divides by the Tukey window's overlap: a few
  // tenths of a pixel off at most, well inside the 3 % agreement.)
  return check.found && std::abs(check.length_px - len.length_px) <= std::max(2.0, 0.03 * len.length_px);
}

}  // namespace

StreakEnd find_streak_end(const cv::Mat& gray, const StreakAxis& axis, bool axis_refined,
                          const StreakSearch& search, const SensorPattern& pattern, bool pattern_out,
                          bool well_lit, const GvsEstimatorSettings& set, SpectrumWorkspace& ws) {
  StreakEnd end;
  const StreakLength& len = end.length;
  // An axis not refined may be a few degrees off: the end is looked for
  // beside the ray too, and its lag then gives the axis (motion_axis).
  const double axis_tan = axis_refined ? 0.0 : std::tan(set.unrefined_axis_error_deg * kPi / 180.0);
  if (search.hi_px > search.lo_px + 2.0) {
    end.length =
        ws.blur.streak_length(ws.spectrum, axis, search.lo_px, search.hi_px, search.expected_px, axis_tan);
  }
  // The power cepstrum: a second reading of the same streak that weighs
  // every zero of the blur alike, read only where needed, once.
  bool cepstrum_read = false;
  double cepstrum_px = 0.0;  // 0: it found no end
  double cepstrum_significance = 0.0;
  const auto cepstrum_within = [&](double tolerance) {
    // The cepstrum sees the ground's own troughs too (a fixed lag of its
    // grain): it vouches only where it looks at every length the recent
    // speed allows, beyond the window too (cepstrum_max_streak_fraction),
    // not for a trough found below a streak that may have outgrown its range.
    if (!search.cepstrum_sees_all) return false;
    if (!cepstrum_read) {
      const StreakLength c =
          ws.blur.streak_length_cepstral(ws.spectrum, axis, search.lo_px, search.cepstrum_hi_px);
      cepstrum_px = c.found ? c.length_px : 0.0;
      cepstrum_significance = c.significance;
      cepstrum_read = true;
    }
    return cepstrum_px > 0.0 && std::abs(cepstrum_px - len.length_px) <= tolerance * len.length_px;
  };
  const bool cold = search.min_length_px >= set.min_streak_px_cold;
  // Around a recent speed the two readings may lie further apart
  // (cepstrum_max_disagreement_tracked): their mean is then the length.
  const double vouch_tolerance = cold ? set.cepstrum_max_disagreement : set.cepstrum_max_disagreement_tracked;
  const auto vouched = [&] { return cepstrum_within(vouch_tolerance); };
  const auto passes = [&](const StreakLength& l, double min_significance, double max_background) {
    return l.found && l.depth >= set.min_streak_depth && l.significance >= min_significance &&
           l.background <= max_background && l.length_px > search.lo_px + 0.5 && l.length_px < search.hi_px - 0.5;
  };
  const auto passes_gates = [&](const StreakLength& l) {
    return passes(l, search.min_significance, search.max_background);
  };
  // Without a recent speed the cold gates hold, unless the power cepstrum,
  // a second reading that looks beyond the window, stands witness: an end
  // it puts at the same length needs only the tracked gates (ph_asphalt_04
  // at 14.4 km/h, 3 ms: the true 120 px ends stand at significance 3-5,
  // each at the cepstrum's deepest point) where
  //  - an older speed bounds every length the streak can have now within
  //    the cepstrum's reach (StreakSearch::reacquire), or
  //  - the cepstrum's end stands out as far as the tracked bar asks of the
  //    streak end, and the spectrum is no more elongated than a streak of
  //    that length makes this ground's (a longer one elongates it more).
  // Under a streak longer than the reach both readings can find the same
  // trough of the grain (acg_Asphalt025C, 3 ms at 60 km/h: 113 px for
  // 500 px; the cepstrum's end there stands at 0.5-0.8 of the ray's spread,
  // or the spectrum is more elongated than 113 px make it).
  const auto witnessed = [&] {
    if (!passes(len, set.min_streak_significance, set.max_streak_background_tracked) || !vouched()) return false;
    const bool bounded = search.reacquire && len.length_px >= search.reacquire_lo_px &&
                         len.length_px <= search.reacquire_hi_px;
    return bounded || (cepstrum_significance >= set.min_streak_significance &&
                       axis.anisotropy <= ws.blur.streak_anisotropy(ws.spectrum, axis, len.length_px));
  };
  // With a recent speed, an end under the tracked gates counts where the
  // cepstrum stands witness the same way: its own end within
  // cepstrum_max_disagreement_tracked, standing out by the tracked bar. The
  // two readings weigh the spectrum differently (every zero alike; the
  // strongest |k|), so a trough of the grain in one seldom sits in the
  // other at the same length, and the recent speed has already narrowed
  // the search. ph_asphalt_04 at 14.4 km/h, 3 ms: true 120 px ends at
  // significance 2.9-3.5 or background 0.13-0.2; over 70 replays (every
  // ground, every exposure mode, seeds 1-4) the ends this admits lie within
  // 3.5 % of the truth (docs/estimator.md, "Measures against false answers").
  const auto corroborated = [&] {
    return passes(len, set.min_streak_significance_witnessed, set.max_streak_background_witnessed) && vouched() &&
           cepstrum_significance >= set.min_streak_significance;
  };
  const bool accepted = passes_gates(len) || (cold ? witnessed() : corroborated());
  // The cepstrum's own end stands out by the tracked bar (read it first).
  const auto cepstrum_stands_out = [&] { return cepstrum_significance >= set.min_streak_significance; };
  // It chooses between rival ends only where it agrees closely and stands
  // out: at 3 % from a trough of the grain it is that trough too
  // (acg_Asphalt025C at 0.1 mm per photo pixel, `const` seed 1 frame 304:
  // a 188 px streak, rivals, both readings at 165-168 px with the cepstrum
  // standing out 1.5: 11 % slow at quality 0.45).
  const auto cepstrum_decides = [&] {
    return cepstrum_within(set.cepstrum_max_disagreement) && cepstrum_stands_out();
  };
  // Rival ends as deep as an accepted one: the length the recent speed
  // predicts cannot choose, it lags an accelerating car (`const adaptive
  // under` seed 1 frame 309: 70 px predicted, the end at 75 px and a
  // trough at 70 px that would read 6 % slow at quality 0.39). The cepstrum
  // decides: the end nearest to its length, and no speed unless they agree.
  // Choosing between ends a few percent apart takes the close agreement
  // (cepstrum_max_disagreement), also around a recent speed.
  if (accepted && len.rivals > 0 && !cepstrum_decides()) {
    end.ambiguous = true;
    if (cepstrum_px > 0.0) {
      const StreakLength nearest =
          ws.blur.streak_length_again(search.lo_px, search.hi_px, cepstrum_px, axis_tan);
      if (passes_gates(nearest) && cepstrum_stands_out() &&
          std::abs(nearest.length_px - cepstrum_px) <= set.cepstrum_max_disagreement * nearest.length_px) {
        end.length = nearest;
        end.ambiguous = false;
      }
    }
  }
  // Without a recent speed, the spectrum must also be no more elongated than
  // a streak twice as long would make on this ground (blur_consistency.cpp):
  // a short "streak end" in a spectrum of endless streaks is texture. The
  // ground's own spectrum sets the scale: on fine grain (torcs_etrack2) a
  // true 28-56 px streak is as elongated (0.95-0.97) as a 150 px one on the
  // simulator's asphalt.
  const bool consistent =
      !cold || (accepted && axis.anisotropy <= ws.blur.streak_anisotropy(ws.spectrum, axis, 2.0 * len.length_px));
  // A clear streak end: its lag gives the axis from axis_from_streak_end_px,
  // its length the speed from min_length.
  // A dark frame gives a speed only from a streak end up to
  // dark_max_streak_px: in 10-seed `const`/`accel` under-exposed runs, ends
  // of 107-162 px were found 5-25 % short (6 frames; measurements: commit
  // 944efc3).
  // A well-lit frame with a faint texture is blurred, not dark (a streak of
  // L px keeps about 1/L of the texture's power): its streak end counts down
  // to min_speed_texture_snr_lit when the cepstrum puts it at the same
  // length (cepstrum_max_disagreement); so does a well-lit frame's end
  // beyond dark_max_streak_px (docs/estimator.md, "Faint streaks on
  // well-lit ground").
  const bool faint = axis.texture_snr < set.min_speed_texture_snr;
  const bool lit_faint = well_lit && axis.texture_snr >= set.min_speed_texture_snr_lit;
  end.shorter_than_search = len.found && len.depth >= set.min_streak_depth &&
                            len.significance >= search.min_significance && len.length_px <= search.lo_px + 0.5;
  // Without a recent speed the witness must also stand out as `witnessed`
  // asks: both readings can find the same trough of the grain
  // (torcs_wheel1 `skidpad` at 43 km/h: a 360 px streak's frame, faint,
  // read 164 px at significance 6.0, the cepstrum at 163.5 px standing
  // out 1.2 where a true end's stands out 3.5 or more).
  end.clear = consistent && accepted && (!faint || (lit_faint && vouched() && (!cold || cepstrum_stands_out())));
  const bool beyond_dark_max = pattern_out && len.length_px > set.dark_max_streak_px;
  end.has_speed = end.clear && !end.ambiguous && len.length_px >= search.min_length_px &&
                  !(beyond_dark_max && !(well_lit && vouched()));
  // Two readings of one end, each off by its own texture: the speed takes
  // their mean (the lag keeps its direction).
  if (end.has_speed && cepstrum_read && vouched()) {
    const double scale = 0.5 * (1.0 + cepstrum_px / len.length_px);
    end.length.length_px *= scale;
    end.length.d_row_px *= scale;
    end.length.d_col_px *= scale;
  }
  if (end.has_speed && cold) {
    end.has_speed = not_an_alias(gray, axis, len, search, pattern, pattern_out, axis_tan, ws);
    // An alias's lag is not on the axis either: (frame - L', -d_across).
    end.clear = end.has_speed;
  }
  return end;
}

}  // namespace gvs::dsp
