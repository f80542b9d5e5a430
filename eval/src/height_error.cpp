#include "gvs/eval/height_error.hpp"

#include <cmath>
#include <cstdio>
#include <unordered_map>

#include "gvs/core/geometry.hpp"

namespace gvs::eval {
namespace {

struct Samples {
  std::vector<double> dh, speed, scale, corrected;
};

void finish(HeightBin& b, const Samples& s) {
  b.height_error_mm = error_stats(s.dh);
  b.speed_pct = error_stats(s.speed);
  b.scale_pct = error_stats(s.scale);
  b.corrected_pct = error_stats(s.corrected);
}

std::string line(const HeightBin& b, const char* label) {
  auto cell = [&](const ErrorStats& s, double v, int decimals) {
    if (s.count == 0) return std::string("-");
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.*f", decimals, v);
    return std::string(buf);
  };
  char out[256];
  std::snprintf(out, sizeof out, "%-15s %6zu %7s | %7s %7s %7s | %7s | %7s %7s\n", label, b.speed_pct.count,
                cell(b.height_error_mm, b.height_error_mm.mean, 2).c_str(), cell(b.speed_pct, b.speed_pct.mean, 2).c_str(),
                cell(b.speed_pct, b.speed_pct.rms, 2).c_str(), cell(b.speed_pct, b.speed_pct.max_abs, 2).c_str(),
                cell(b.scale_pct, b.scale_pct.mean, 2).c_str(), cell(b.corrected_pct, b.corrected_pct.rms, 2).c_str(),
                cell(b.corrected_pct, b.corrected_pct.max_abs, 2).c_str());
  return out;
}

}  // namespace

const std::vector<double>& height_bin_edges_mm() {
  static const std::vector<double> edges = {-16.0, -6.0, -4.0, -2.0, -0.5, 0.5, 2.0, 4.0, 6.0, 10.0, 16.0};
  return edges;
}

std::optional<HeightReport> evaluate_speed_vs_height(const std::vector<drivers::TruthRecord>& truth,
                                                     const std::vector<drivers::EstimateRow>& estimates,
                                                     double nominal_mm) {
  bool any = false;
  for (const auto& t : truth) any = any || t.height_mm.has_value();
  if (!any || !(nominal_mm > 0.0)) return std::nullopt;
  std::unordered_map<std::int64_t, const drivers::EstimateRow*> by_index;
  for (const auto& row : estimates) by_index[row.estimate.index] = &row;

  const auto& edges = height_bin_edges_mm();
  HeightReport r;
  r.nominal_mm = nominal_mm;
  r.bins.resize(edges.size() - 1);
  std::vector<Samples> samples(r.bins.size());
  Samples all;
  for (std::size_t i = 0; i + 1 < edges.size(); ++i) {
    r.bins[i].lo_mm = edges[i];
    r.bins[i].hi_mm = edges[i + 1];
  }
  r.all.lo_mm = edges.front();
  r.all.hi_mm = edges.back();
  double sxy = 0.0, sxx = 0.0, sx = 0.0, sy = 0.0;
  for (const auto& t : truth) {
    const auto it = by_index.find(t.index);
    if (it == by_index.end() || !it->second->estimate.has_speed) continue;
    if (core::mps_to_kmh(t.speed_mps) < kMovingKmh) continue;
    const double h = t.height_mm.value_or(nominal_mm);
    const double dh = h - nominal_mm;
    const double v = it->second->estimate.speed_mps;
    const double speed = (v - t.speed_mps) / t.speed_mps * 100.0;
    const double scale = (nominal_mm / h - 1.0) * 100.0;
    const double corrected = (v * h / nominal_mm - t.speed_mps) / t.speed_mps * 100.0;
    for (std::size_t i = 0; i < r.bins.size(); ++i) {
      if (dh >= edges[i] && dh < edges[i + 1]) {
        samples[i].dh.push_back(dh);
        samples[i].speed.push_back(speed);
        samples[i].scale.push_back(scale);
        samples[i].corrected.push_back(corrected);
      }
    }
    all.dh.push_back(dh);
    all.speed.push_back(speed);
    all.scale.push_back(scale);
    all.corrected.push_back(corrected);
    sx += dh;
    sy += speed;
    sxy += dh * speed;
    sxx += dh * dh;
  }
  for (std::size_t i = 0; i < r.bins.size(); ++i) finish(r.bins[i], samples[i]);
  finish(r.all, all);
  const auto n = static_cast<double>(all.dh.size());
  const double var = sxx - sx * sx / std::max(n, 1.0);
  r.slope_pct_per_mm = n > 1.0 && var > 0.0 ? (sxy - sx * sy / n) / var : 0.0;
  return r;
}

std::string format_height_table(const HeightReport& r) {
  char buf[256];
  std::snprintf(buf, sizeof buf,
                "speed against height (nominal %.1f mm; moving frames with a speed; scale = (H0/H - 1), "
                "corrected = speed with the true height):\n",
                r.nominal_mm);
  std::string out = buf;
  out += "height error      frames    mean |   speed error (%)       |   scale | corrected (%)\n";
  out += "(mm)                        (mm) |    mean     rms     max |    mean |     rms     max\n";
  for (const HeightBin& b : r.bins) {
    if (b.speed_pct.count == 0) continue;
    std::snprintf(buf, sizeof buf, "[%+.1f, %+.1f)", b.lo_mm, b.hi_mm);
    out += line(b, buf);
  }
  out += line(r.all, "all");
  std::snprintf(buf, sizeof buf, "slope: %.2f %% of speed per mm of height (the scale alone: %.2f)\n",
                r.slope_pct_per_mm, -100.0 / r.nominal_mm);
  out += buf;
  return out;
}

}  // namespace gvs::eval
