#include "gvs/eval/accuracy.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <unordered_map>

#include <nlohmann/json.hpp>

#include "gvs/can/codec.hpp"
#include "gvs/core/geometry.hpp"

namespace gvs::eval {

namespace {

struct Errors {
  std::vector<double> direction, speed_pct, yaw;
};

ConstantDirectionSummary summarise_direction(double truth_deg, std::vector<double> values) {
  ConstantDirectionSummary s;
  s.truth_deg = truth_deg;
  s.count = values.size();
  if (values.empty()) return s;
  // Unwrap around the truth so a run near +-180 deg summarises sensibly.
  for (double& v : values) v = truth_deg + core::wrap_deg(v - truth_deg);
  const ErrorStats st = error_stats(values);
  s.mean = st.mean;
  s.std = st.std;
  s.min = *std::min_element(values.begin(), values.end());
  s.max = *std::max_element(values.begin(), values.end());
  std::map<long long, std::size_t> bins;
  for (double v : values) ++bins[std::llround(v * 10.0)];
  const auto best = std::max_element(bins.begin(), bins.end(),
                                     [](const auto& a, const auto& b) { return a.second < b.second; });
  s.mode = static_cast<double>(best->first) / 10.0;
  return s;
}

void finish(BandAccuracy& b, const Errors& e) {
  b.direction_deg = error_stats(e.direction);
  b.speed_pct = error_stats(e.speed_pct);
  b.yaw_rate_dps = error_stats(e.yaw);
}

}  // namespace

ErrorStats error_stats(const std::vector<double>& errors) {
  ErrorStats s;
  s.count = errors.size();
  if (errors.empty()) return s;
  double sum = 0.0;
  double sum_sq = 0.0;
  for (double e : errors) {
    sum += e;
    sum_sq += e * e;
    s.max_abs = std::max(s.max_abs, std::abs(e));
  }
  const auto n = static_cast<double>(errors.size());
  s.mean = sum / n;
  s.rms = std::sqrt(sum_sq / n);
  double var = 0.0;
  for (double e : errors) var += (e - s.mean) * (e - s.mean);
  s.std = errors.size() > 1 ? std::sqrt(var / (n - 1.0)) : 0.0;
  return s;
}

const double kBusMinQuality = can::ValidityRule{}.min_quality;

const std::vector<std::pair<double, double>>& speed_bands_kmh() {
  static const std::vector<std::pair<double, double>> bands = {
      {0.0, 5.0}, {5.0, 15.0}, {15.0, 60.0}, {60.0, 140.0}, {140.0, 250.0}};
  return bands;
}

AccuracyReport evaluate_accuracy(const std::vector<drivers::TruthRecord>& truth,
                                 const std::vector<drivers::EstimateRow>& estimates) {
  AccuracyReport r;
  const auto& band_limits = speed_bands_kmh();
  r.bands.resize(band_limits.size());
  std::vector<Errors> band_errors(band_limits.size());
  Errors all_errors;
  for (std::size_t i = 0; i < band_limits.size(); ++i) {
    r.bands[i].lo_kmh = band_limits[i].first;
    r.bands[i].hi_kmh = band_limits[i].second;
  }
  r.all.lo_kmh = band_limits.front().first;
  r.all.hi_kmh = band_limits.back().second;

  std::unordered_map<std::int64_t, const drivers::EstimateRow*> by_index;
  for (const auto& row : estimates) by_index[row.estimate.index] = &row;

  // Constant-direction run: every moving truth row has the same direction.
  double dir_min = 1e9;
  double dir_max = -1e9;
  std::size_t moving_rows = 0;
  for (const auto& t : truth) {
    if (t.direction_deg && core::mps_to_kmh(t.speed_mps) >= kMovingKmh) {
      dir_min = std::min(dir_min, *t.direction_deg);
      dir_max = std::max(dir_max, *t.direction_deg);
      ++moving_rows;
    }
  }
  const bool constant_direction = moving_rows > 0 && dir_max - dir_min < 0.01;
  std::vector<double> constant_dir_values;

  std::size_t matched = 0;
  for (const auto& t : truth) {
    const auto it = by_index.find(t.index);
    const core::VelocityEstimate* e = it == by_index.end() ? nullptr : &it->second->estimate;
    if (e == nullptr) {
      ++r.truth_without_estimate;
      continue;
    }
    ++matched;
    const double kmh = core::mps_to_kmh(t.speed_mps);
    if (t.speed_mps < core::VelocityEstimate::kStandstillMps) {
      ++r.standstill_frames;
      if (e->has_speed) {
        ++r.standstill_with_speed;
        r.standstill_speed_max_abs_mps = std::max(r.standstill_speed_max_abs_mps, std::abs(e->speed_mps));
      }
      if (e->has_direction) ++r.standstill_with_direction;
    }
    std::size_t b = band_limits.size();
    for (std::size_t i = 0; i < band_limits.size(); ++i) {
      const bool last = i + 1 == band_limits.size();
      if (kmh >= band_limits[i].first && (kmh < band_limits[i].second || (last && kmh <= band_limits[i].second))) {
        b = i;
      }
    }
    for (BandAccuracy* band : {b < r.bands.size() ? &r.bands[b] : nullptr, &r.all}) {
      if (band == nullptr) continue;
      Errors& errs = band == &r.all ? all_errors : band_errors[b];
      ++band->frames;
      const bool moving = kmh >= kMovingKmh;
      if (moving) ++band->moving_frames;
      const bool valid = can::quality_passes(e->quality, kBusMinQuality);
      if (e->has_speed) ++band->with_speed;
      if (e->has_speed && valid) ++band->valid_speed;
      if (moving && e->has_direction && t.direction_deg) {
        ++band->with_direction;
        if (valid) ++band->valid_direction;
        errs.direction.push_back(core::wrap_deg(e->direction_deg - *t.direction_deg));
      }
      if (moving && e->has_speed) {
        const double pct = (e->speed_mps - t.speed_mps) / t.speed_mps * 100.0;
        errs.speed_pct.push_back(pct);
        if (kmh >= kWrongSpeedMinKmh && std::abs(pct) > kWrongSpeedPct) ++band->speed_off;
      }
      if (e->has_yaw_rate && std::isfinite(t.yaw_rate_dps)) errs.yaw.push_back(e->yaw_rate_dps - t.yaw_rate_dps);
    }
    if (constant_direction && kmh >= kMovingKmh && e->has_direction) constant_dir_values.push_back(e->direction_deg);
  }
  for (std::size_t i = 0; i < r.bands.size(); ++i) finish(r.bands[i], band_errors[i]);
  finish(r.all, all_errors);
  r.estimates_without_truth = estimates.size() - matched;
  if (constant_direction) r.constant_direction = summarise_direction(dir_min, constant_dir_values);
  return r;
}

namespace {

std::string cell(std::size_t count, double v, int decimals) {
  if (count == 0) return "-";
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.*f", decimals, v);
  return buf;
}

std::string band_line(const BandAccuracy& b, const char* label_override = nullptr) {
  char label[32];
  if (label_override != nullptr) {
    std::snprintf(label, sizeof label, "%s", label_override);
  } else {
    std::snprintf(label, sizeof label, "%.0f-%.0f", b.lo_kmh, b.hi_kmh);
  }
  char coverage_dir[32];
  char coverage_speed[32];
  std::snprintf(coverage_dir, sizeof coverage_dir, "%zu/%zu", b.with_direction, b.moving_frames);
  std::snprintf(coverage_speed, sizeof coverage_speed, "%zu/%zu", b.with_speed, b.frames);
  const ErrorStats& d = b.direction_deg;
  const ErrorStats& s = b.speed_pct;
  const ErrorStats& y = b.yaw_rate_dps;
  char line[512];
  std::snprintf(line, sizeof line, "%-9s %6zu %11s %11s | %8s %7s %7s %7s | %8s %7s %7zu | %7s",
                label, b.frames, coverage_dir, coverage_speed, cell(d.count, d.mean, 3).c_str(),
                cell(d.count, d.std, 3).c_str(), cell(d.count, d.rms, 3).c_str(), cell(d.count, d.max_abs, 2).c_str(),
                cell(s.count, s.mean, 2).c_str(), cell(s.count, s.rms, 2).c_str(), b.speed_off,
                cell(y.count, y.rms, 2).c_str());
  return line;
}

nlohmann::json stats_json(const ErrorStats& s) {
  return {{"count", s.count}, {"mean", s.mean}, {"std", s.std}, {"rms", s.rms}, {"max_abs", s.max_abs}};
}

nlohmann::json band_json(const BandAccuracy& b) {
  return {{"lo_kmh", b.lo_kmh},
          {"hi_kmh", b.hi_kmh},
          {"frames", b.frames},
          {"moving_frames", b.moving_frames},
          {"with_direction", b.with_direction},
          {"with_speed", b.with_speed},
          {"valid_direction", b.valid_direction},
          {"valid_speed", b.valid_speed},
          {"direction_deg", stats_json(b.direction_deg)},
          {"speed_pct", stats_json(b.speed_pct)},
          {"yaw_rate_dps", stats_json(b.yaw_rate_dps)},
          {"speed_off_5pct", b.speed_off}};
}

/// "valid on the bus (quality >= 0.30), direction/moving speed/all: 0-5 300/300 384/385; ...":
/// the coverage the ECU sees; the table's counts take every quality.
std::string valid_line(const AccuracyReport& r) {
  char buf[96];
  std::snprintf(buf, sizeof buf, "valid on the bus (quality >= %.2f), direction/moving speed/all:", kBusMinQuality);
  std::string out = buf;
  const auto add = [&](const BandAccuracy& b, const char* label) {
    std::snprintf(buf, sizeof buf, " %s %zu/%zu %zu/%zu", label, b.valid_direction, b.moving_frames, b.valid_speed,
                  b.frames);
    out += buf;
  };
  for (const BandAccuracy& b : r.bands) {
    if (b.frames == 0) continue;
    char label[32];
    std::snprintf(label, sizeof label, "%.0f-%.0f", b.lo_kmh, b.hi_kmh);
    add(b, label);
    out += ';';
  }
  add(r.all, "all");
  return out + '\n';
}

}  // namespace

std::string format_accuracy_table(const AccuracyReport& r) {
  std::string out;
  out += "band km/h frames   direction       speed | direction error (deg)           | speed error (%)          | yaw (dps)\n";
  out += "                     frames/moving  /all |     mean     std     rms     max |     mean     rms   off>5 |     rms\n";
  for (const BandAccuracy& b : r.bands) out += band_line(b) + '\n';
  out += band_line(r.all, "all") + '\n';
  out += valid_line(r);
  char buf[256];
  if (r.standstill_frames > 0) {
    std::snprintf(buf, sizeof buf,
                  "standstill: %zu frames, speed on %zu (max |speed| %.4f m/s), direction on %zu (should be 0)\n",
                  r.standstill_frames, r.standstill_with_speed, r.standstill_speed_max_abs_mps,
                  r.standstill_with_direction);
    out += buf;
  }
  if (r.truth_without_estimate > 0 || r.estimates_without_truth > 0) {
    std::snprintf(buf, sizeof buf, "unmatched: %zu truth rows without an estimate row, %zu estimate rows without truth\n",
                  r.truth_without_estimate, r.estimates_without_truth);
    out += buf;
  }
  if (r.constant_direction) {
    const ConstantDirectionSummary& c = *r.constant_direction;
    std::snprintf(buf, sizeof buf,
                  "constant direction %.2f deg (thesis Tab. 4.3 style), %zu estimates: mean %.3f  std %.3f  mode %.1f  "
                  "min %.2f  max %.2f deg\n",
                  c.truth_deg, c.count, c.mean, c.std, c.mode, c.min, c.max);
    out += buf;
  }
  return out;
}

std::string format_accuracy_json(const AccuracyReport& r) {
  nlohmann::json j;
  j["bands"] = nlohmann::json::array();
  for (const BandAccuracy& b : r.bands) j["bands"].push_back(band_json(b));
  j["all"] = band_json(r.all);
  j["standstill"] = {{"frames", r.standstill_frames},
                     {"with_speed", r.standstill_with_speed},
                     {"speed_max_abs_mps", r.standstill_speed_max_abs_mps},
                     {"with_direction", r.standstill_with_direction}};
  j["truth_without_estimate"] = r.truth_without_estimate;
  j["estimates_without_truth"] = r.estimates_without_truth;
  if (r.constant_direction) {
    const ConstantDirectionSummary& c = *r.constant_direction;
    j["constant_direction"] = {{"truth_deg", c.truth_deg}, {"count", c.count}, {"mean", c.mean}, {"std", c.std},
                               {"mode", c.mode},           {"min", c.min},     {"max", c.max}};
  }
  return j.dump(2);
}

}  // namespace gvs::eval
