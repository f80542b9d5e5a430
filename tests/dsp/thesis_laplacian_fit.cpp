// Fits the thesis's Laplacian speed model (thesis 5.3, Fig. 5.7) on gvs's
// simulator and prints it as the C++ table for dsp/src/thesis/laplacian.cpp.
//
//   thesis_laplacian_fit [seeds=2]
//
// Renders the "accel" (0 -> 140 km/h straight ahead) and "const" (steps of
// 1 ... 140 km/h) scenarios with 3 ms continuous exposure, normal light,
// 512x384 px at 0.1 mm/px, for seeds 1..N, measures lap_std on every frame, takes the median lap_std around
// each knot speed and joins the knots with exponential pieces
// lap_std = a * exp(b * v) (continuous, so the inverse needs no extra
// switching rule). Then checks the model on seed N+1 and prints the speed
// errors per speed band.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "gvs/drivers/simulator.hpp"
#include "gvs/dsp/thesis.hpp"

namespace {

using gvs::dsp::thesis::LaplacianSegment;

struct Sample {
  double speed_mps;
  double lap_std;
};

std::vector<Sample> render(std::uint64_t seed, const char* scenario) {
  gvs::drivers::SimulatorConfig cfg;
  cfg.scenario = scenario;
  cfg.seed = seed;
  cfg.exposure_us = 3000.0;
  gvs::drivers::Simulator sim(cfg);
  gvs::dsp::thesis::LaplacianBlur lap(cfg.camera.mm_per_px);
  std::vector<Sample> out;
  gvs::drivers::SimFrame f;
  while (sim.next(f)) out.push_back({f.truth.speed_mps, lap.lap_std(f.gray)});
  return out;
}

/// Both speed-sweeping scenarios: "accel" (0 -> 140 km/h, straight) and
/// "const" (1 s each at 1, 2, 5, 10, 20, 40, 70, 100, 140 km/h, 10 deg).
std::vector<Sample> render_both(std::uint64_t seed) {
  std::vector<Sample> out = render(seed, "accel");
  const auto c = render(seed, "const");
  out.insert(out.end(), c.begin(), c.end());
  return out;
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 == 1 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

}  // namespace

int main(int argc, char** argv) {
  const int seeds = argc > 1 ? std::max(1, std::atoi(argv[1])) : 2;
  // Knots: dense where blur grows fast (low speed); the "const" speeds and
  // 15 km/h (the thesis's switch) included.
  const std::vector<double> knots{0.0,  1.0 / 3.6,  2.0 / 3.6,  1.0,  5.0 / 3.6,  2.0,   10.0 / 3.6,
                                  3.5,  15.0 / 3.6, 20.0 / 3.6, 7.0,  8.5,        40.0 / 3.6, 14.0,
                                  70.0 / 3.6, 100.0 / 3.6, 140.0 / 3.6};
  std::vector<Sample> fit;
  for (int s = 1; s <= seeds; ++s) {
    const auto part = render_both(static_cast<std::uint64_t>(s));
    fit.insert(fit.end(), part.begin(), part.end());
  }
  std::printf("# %zu frames from seeds 1..%d of 'accel' and 'const'\n", fit.size(), seeds);
  std::printf("# knot_mps  samples  median_lap_std  spread(p90-p10)/median\n");
  std::vector<double> kv;
  std::vector<double> ks;
  for (std::size_t i = 0; i < knots.size(); ++i) {
    const double lo = i == 0 ? knots[0] - 0.1 : 0.5 * (knots[i - 1] + knots[i]);
    const double hi = i + 1 == knots.size() ? knots[i] + 0.5 : 0.5 * (knots[i] + knots[i + 1]);
    // Samples within +-(0.1 + 10 %) of the knot, never past the neighbours' midpoints.
    const double half = std::min({knots[i] - lo, hi - knots[i], 0.1 + 0.1 * knots[i]});
    std::vector<double> v;
    for (const Sample& x : fit) {
      if (std::abs(x.speed_mps - knots[i]) <= std::max(half, 0.05)) v.push_back(x.lap_std);
    }
    if (v.size() < 3) {
      std::printf("# %7.2f  %5zu  (too few samples, skipped)\n", knots[i], v.size());
      continue;
    }
    std::vector<double> sorted = v;
    std::sort(sorted.begin(), sorted.end());
    const double p10 = sorted[sorted.size() / 10];
    const double p90 = sorted[sorted.size() * 9 / 10];
    const double m = median(v);
    std::printf("# %7.2f  %5zu  %10.4f  %6.3f\n", knots[i], v.size(), m, (p90 - p10) / m);
    if (!ks.empty() && m >= ks.back()) {
      std::printf("# lap_std stops falling at %.2f m/s: the model ends at %.2f m/s\n", knots[i], kv.back());
      break;
    }
    kv.push_back(knots[i]);
    ks.push_back(m);
  }
  if (kv.size() < 2) {
    std::fprintf(stderr, "thesis_laplacian_fit: fewer than two usable knots; nothing fitted\n");
    return 1;
  }
  std::vector<LaplacianSegment> model;
  for (std::size_t i = 0; i + 1 < kv.size(); ++i) {
    const double b = std::log(ks[i + 1] / ks[i]) / (kv[i + 1] - kv[i]);
    model.push_back({kv[i], kv[i + 1], ks[i] * std::exp(-b * kv[i]), b});
  }
  std::printf("constexpr std::array<LaplacianSegment, %zu> kFittedModel{{\n", model.size());
  for (const auto& s : model) {
    std::printf("    {%.4f, %.4f, %.9g, %.9g},\n", s.speed_lo_mps, s.speed_hi_mps, s.a, s.b);  // knots to 4 decimals
  }
  std::printf("}};\n");

  // Check on an unseen seed.
  const auto check = render_both(static_cast<std::uint64_t>(seeds + 1));
  const double bands[] = {0.0, 15.0 / 3.6, 10.0, 20.0, 40.0};
  std::printf("# check on seed %d: speed error by truth band\n", seeds + 1);
  std::printf("# band_mps        frames  mean_err_mps  rms_err_mps  median_abs_rel_err\n");
  for (std::size_t b = 0; b + 1 < std::size(bands); ++b) {
    std::vector<double> rel;
    double sum = 0.0;
    double sq = 0.0;
    int n = 0;
    for (const Sample& x : check) {
      if (x.speed_mps < bands[b] || x.speed_mps >= bands[b + 1]) continue;
      const auto sp = gvs::dsp::thesis::invert_laplacian_model(x.lap_std, model);
      if (!sp.ok) continue;
      const double e = sp.speed_mps - x.speed_mps;
      sum += e;
      sq += e * e;
      ++n;
      if (x.speed_mps > 0.05) rel.push_back(std::abs(e) / x.speed_mps);
    }
    if (n == 0) continue;
    std::printf("# %5.2f-%5.2f  %6d  %10.3f  %10.3f  %8.3f\n", bands[b], bands[b + 1], n, sum / n, std::sqrt(sq / n),
                rel.empty() ? 0.0 : median(rel));
  }
  return 0;
}
