#include "gvs/eval/speed_gaps.hpp"

#include <algorithm>
#include <cmath>
#include <unordered_map>

#include <fmt/format.h>

#include "gvs/core/geometry.hpp"
#include "gvs/dsp/gvs_settings.hpp"
#include "gvs/eval/accuracy.hpp"

namespace gvs::eval {

namespace {

using core::Method;

/// The streak a frame's truth and exposure imply, and the longest the gvs
/// estimator measures along it (GvsEstimatorSettings::max_streak_fraction
/// of the frame's extent in the streak's direction, as analyse_streak takes it).
struct FrameFacts {
  double speed_kmh = 0.0;
  double light_us = 0.0;
  double streak_px = 0.0;
  double measurable_px = 0.0;
  bool pulsed = false;
};

FrameFacts frame_facts(const drivers::TruthRecord& t, const core::ExposurePlan& exposure,
                       const core::CameraGeometry& cam) {
  const dsp::GvsEstimatorSettings set;
  FrameFacts f;
  f.speed_kmh = core::mps_to_kmh(t.speed_mps);
  f.light_us = exposure.lit_time_us();
  f.pulsed = exposure.pulse_count > 0;
  f.streak_px = t.speed_mps * f.light_us * 1e-6 / (cam.mm_per_px * 1e-3);
  double extent_px = std::min(cam.width_px, cam.height_px);
  if (t.direction_deg) {
    const double a = core::deg_to_rad(*t.direction_deg);
    // Camera axes: x along the image rows (down), y along the columns.
    const core::Vec2 u = core::vehicle_to_camera({std::cos(a), std::sin(a)}, cam.mount_yaw_deg);
    extent_px = std::abs(u.x) * cam.height_px + std::abs(u.y) * cam.width_px;
  }
  f.measurable_px = set.max_streak_fraction * extent_px;
  return f;
}

/// The gvs estimator's outcomes that say something about the streak; the
/// others (light, frame checks, thesis methods) speak for themselves.
bool streak_outcome(Method m) {
  switch (m) {
    case Method::no_match:
    case Method::no_texture:
    case Method::short_streak:
    case Method::blur_cont:
    case Method::blur_energy:
    case Method::blur_fwd:
    case Method::streak_cont:
    case Method::streak_energy:
    case Method::streak_fwd:
      return true;
    default:
      return false;
  }
}

SpeedGapCause classify(Method m, const std::optional<FrameFacts>& f) {
  if (!f || f->pulsed || !streak_outcome(m)) return SpeedGapCause::other;
  const dsp::GvsEstimatorSettings set;
  if (f->streak_px > f->measurable_px) return SpeedGapCause::streak_too_long;
  if (f->streak_px < set.min_streak_px_cold && m != Method::no_texture) return SpeedGapCause::streak_too_short;
  if (m != Method::no_texture && m != Method::no_match) return SpeedGapCause::streak_unclear;
  return SpeedGapCause::other;
}

void add_frame(SpeedGap& g, Method m, std::int64_t index, const std::optional<FrameFacts>& f) {
  const bool first = g.indices.empty();
  g.indices.push_back(index);
  auto it = std::find_if(g.methods.begin(), g.methods.end(), [m](const auto& p) { return p.first == m; });
  if (it == g.methods.end()) {
    g.methods.emplace_back(m, 1);
  } else {
    ++it->second;
  }
  if (!f) return;
  (f->pulsed ? g.pulsed : g.continuous) = true;
  const auto widen = [first](double& lo, double& hi, double v) {
    lo = first ? v : std::min(lo, v);
    hi = first ? v : std::max(hi, v);
  };
  widen(g.speed_kmh_min, g.speed_kmh_max, f->speed_kmh);
  widen(g.light_us_min, g.light_us_max, f->light_us);
  widen(g.streak_px_min, g.streak_px_max, f->streak_px);
  widen(g.measurable_px_min, g.measurable_px_max, f->measurable_px);
}

std::string range(double lo, double hi, int decimals) {
  if (fmt::format("{:.{}f}", lo, decimals) == fmt::format("{:.{}f}", hi, decimals)) {
    return fmt::format("{:.{}f}", lo, decimals);
  }
  return fmt::format("{:.{}f}-{:.{}f}", lo, decimals, hi, decimals);
}

/// "0-9, 12, 15-239", at most six runs.
std::string index_runs(const std::vector<std::int64_t>& indices) {
  std::string out;
  int runs = 0;
  for (std::size_t i = 0; i < indices.size();) {
    std::size_t j = i;
    while (j + 1 < indices.size() && indices[j + 1] == indices[j] + 1) ++j;
    if (++runs > 6) return out + ", ...";
    if (!out.empty()) out += ", ";
    out += j == i ? fmt::format("{}", indices[i]) : fmt::format("{}-{}", indices[i], indices[j]);
    i = j + 1;
  }
  return out;
}

std::string streak_sentence(const SpeedGap& g, double mm_per_px) {
  return fmt::format("the streak, speed x exposure / mm_per_px = {} km/h x {} us / {:.3g} mm/px, is {} px",
                     range(g.speed_kmh_min, g.speed_kmh_max, 0), range(g.light_us_min, g.light_us_max, 0), mm_per_px,
                     range(g.streak_px_min, g.streak_px_max, 0));
}

/// Why the gap's frames have no speed and what would measure it.
std::string describe(const SpeedGap& g, const SpeedGapReport& r) {
  const dsp::GvsEstimatorSettings set;
  const double mm_per_px = r.mm_per_px;
  switch (g.cause) {
    case SpeedGapCause::streak_too_long: {
      const std::string too_long = fmt::format(
          "{}, longer than this {}x{} frame measures at this exposure ({:.2f} of the frame along the streak: {} px)",
          streak_sentence(g, mm_per_px), r.width_px, r.height_px, set.max_streak_fraction,
          range(g.measurable_px_min, g.measurable_px_max, 0));
      if (r.first_pulsed_index && g.indices.back() < *r.first_pulsed_index) {
        return fmt::format("{}; the exposure loop's start, before its first double pulse (frame {}) measured it",
                           too_long, *r.first_pulsed_index);
      }
      return too_long +
             "; a double pulse measures it (gvs sim --exposure double-pulse; gvsd's default [exposure] mode), "
             "or a shorter exposure (--exposure adaptive)";
    }
    case SpeedGapCause::streak_too_short:
      return fmt::format(
          "{}, shorter than the {:.0f} px the estimator measures a length from ({:.0f} px while it follows a "
          "speed); a longer exposure measures it (--exposure adaptive), or a double pulse (--exposure double-pulse)",
              streak_sentence(g, mm_per_px), set.min_streak_px_cold, set.min_streak_px);
    case SpeedGapCause::streak_unclear:
      return fmt::format(
          "{}, a measurable length, but its end did not stand out from the texture (little contrast or focus, or "
          "no recent speed to look near); gvs snapshot --frame N shows such a frame",
          streak_sentence(g, mm_per_px));
    case SpeedGapCause::no_estimate_row:
      return "no row in the estimates CSV for these frames (a run of another dataset, or one cut short)";
    case SpeedGapCause::other:
      break;
  }
  const Method m = g.methods.front().first;
  const bool blur = m == Method::blur_cont || m == Method::blur_energy || m == Method::blur_fwd;
  const bool long_streak = m == Method::streak_cont || m == Method::streak_energy || m == Method::streak_fwd;
  // Without truth a blur outcome cannot tell a streak too short from one whose end was unclear.
  std::string text = blur ? "a streak axis, but no length: too short for one, or its end did not stand out "
                            "(on a dataset with truth, gvs snapshot --dataset says which)"
                          : core::method_info(m).description;
  if (long_streak && g.continuous) {
    text += "; a double pulse measures it (gvsd's default [exposure] mode), or a shorter exposure (adaptive)";
  }
  if (g.pulsed && g.light_us_max > 0.0) {
    text += fmt::format(" (light pulses, {} us of light)", range(g.light_us_min, g.light_us_max, 0));
  }
  return text;
}

std::string method_counts(SpeedGap g) {
  std::stable_sort(g.methods.begin(), g.methods.end(), [](const auto& a, const auto& b) { return a.second > b.second; });
  std::string out;
  for (const auto& [m, n] : g.methods) {
    if (!out.empty()) out += ", ";
    out += g.methods.size() == 1 ? std::string(core::method_word(m)) : fmt::format("{} {}", n, core::method_word(m));
  }
  return out;
}

}  // namespace

SpeedGapReport find_speed_gaps(const drivers::DatasetReader& dataset,
                               const std::vector<drivers::EstimateRow>& estimates) {
  SpeedGapReport r;
  const core::CameraGeometry& cam = dataset.camera().geometry;
  r.mm_per_px = cam.mm_per_px;
  r.width_px = cam.width_px;
  r.height_px = cam.height_px;
  std::unordered_map<std::int64_t, const core::VelocityEstimate*> by_index;
  for (const auto& row : estimates) by_index[row.estimate.index] = &row.estimate;
  std::unordered_map<std::int64_t, const core::ExposurePlan*> exposure_of;
  for (const auto& f : dataset.frames()) {
    exposure_of[f.index] = &f.exposure;
    if (f.exposure.pulse_count > 0 && !r.first_pulsed_index) r.first_pulsed_index = f.index;
  }

  for (const drivers::TruthRecord& t : dataset.truth()) {
    if (core::mps_to_kmh(t.speed_mps) < kMovingKmh) continue;
    ++r.moving_frames;
    const auto e = by_index.find(t.index);
    if (e != by_index.end() && e->second->has_speed) continue;
    ++r.without_speed;
    const auto x = exposure_of.find(t.index);
    std::optional<FrameFacts> facts;
    if (x != exposure_of.end()) facts = frame_facts(t, *x->second, cam);
    const Method m = e == by_index.end() ? Method::none : e->second->method;
    const SpeedGapCause cause = e == by_index.end() ? SpeedGapCause::no_estimate_row : classify(m, facts);
    auto g = std::find_if(r.gaps.begin(), r.gaps.end(), [&](const SpeedGap& s) {
      return s.cause == cause && (cause != SpeedGapCause::other || s.methods.front().first == m);
    });
    if (g == r.gaps.end()) {
      r.gaps.push_back({});
      g = std::prev(r.gaps.end());
      g->cause = cause;
    }
    add_frame(*g, m, t.index, facts);
  }
  std::stable_sort(r.gaps.begin(), r.gaps.end(),
                   [](const SpeedGap& a, const SpeedGap& b) { return a.indices.size() > b.indices.size(); });
  return r;
}

std::string format_speed_gaps(const SpeedGapReport& r) {
  if (r.without_speed == 0) return {};
  std::string out = fmt::format("no speed on {} of {} moving frames:\n", r.without_speed, r.moving_frames);
  for (const SpeedGap& g : r.gaps) {
    out += fmt::format("  {} frame{} ({}; frame{} {}): {}\n", g.indices.size(), g.indices.size() == 1 ? "" : "s",
                       method_counts(g), g.indices.size() == 1 ? "" : "s", index_runs(g.indices),
                       describe(g, r));
  }
  return out;
}

std::string why_no_speed(const core::VelocityEstimate& e, const core::ExposurePlan& exposure,
                         const core::CameraGeometry& camera, std::optional<drivers::TruthRecord> truth) {
  if (e.has_speed) return {};
  std::optional<FrameFacts> facts;
  if (truth && core::mps_to_kmh(truth->speed_mps) >= kMovingKmh) facts = frame_facts(*truth, exposure, camera);
  SpeedGap g;
  g.cause = classify(e.method, facts);
  add_frame(g, e.method, e.index, facts);
  if (!facts) (exposure.pulse_count > 0 ? g.pulsed : g.continuous) = true;
  SpeedGapReport context;
  context.mm_per_px = camera.mm_per_px;
  context.width_px = camera.width_px;
  context.height_px = camera.height_px;
  return fmt::format("{}: {}", core::method_word(e.method), describe(g, context));
}

}  // namespace gvs::eval
