// The thesis baseline on gvs's simulator (drivers/src/sim): direction signs
// and the speed switch in vehicle axes, against the simulator's truth.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "gvs/drivers/simulator.hpp"
#include "gvs/dsp/vocabulary.hpp"
#include "gvs/dsp/thesis.hpp"

namespace gvs::dsp {
namespace {

struct Row {
  drivers::TruthRecord truth;
  VelocityEstimate est;
};

std::vector<Row> run(const std::string& scenario, double seconds, const std::string& method, double mount_yaw_deg = 0.0) {
  drivers::SimulatorConfig sc;
  sc.scenario = scenario;
  sc.seconds = seconds;
  sc.seed = 42;
  sc.camera.mount_yaw_deg = mount_yaw_deg;
  drivers::Simulator sim(sc);
  EstimatorConfig ec;
  ec.method = method;
  ec.camera = sc.camera;
  const auto est = make_estimator(ec);
  std::vector<Row> rows;
  drivers::SimFrame f;
  while (sim.next(f)) {
    FrameView v;
    v.gray = f.gray;
    v.index = f.record.index;
    v.t_ns = f.record.t_ns;
    v.exposure = f.record.exposure;
    rows.push_back({f.truth, est->estimate(v)});
  }
  return rows;
}

double median(std::vector<double> v) {
  if (v.empty()) return NAN;
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

// Crawl (below 15 km/h, direction sweeping both ways): ORB frame difference
// gives direction and speed.
TEST(ThesisSim, OrbFollowsCrawlTruth) {
  for (double yaw : {0.0, 20.0}) {
    const auto rows = run("crawl", 2.0, "thesis-orb", yaw);
    std::vector<double> dir_err;
    std::vector<double> speed_rel;
    int measured = 0;
    for (const Row& r : rows) {
      if (!r.est.has_speed) continue;
      ++measured;
      if (r.truth.speed_mps > 0.05 && r.truth.direction_deg && r.est.has_direction) {
        dir_err.push_back(std::abs(wrap_deg(r.est.direction_deg - *r.truth.direction_deg)));
        speed_rel.push_back(std::abs(r.est.speed_mps - r.truth.speed_mps) / r.truth.speed_mps);
      }
    }
    const double md = median(dir_err);
    const double ms = median(speed_rel);
    std::printf("crawl, mount yaw %.0f: %d/%zu frames measured; median |direction error| %.2f deg, median |speed "
                "error| %.1f %%\n",
                yaw, measured, rows.size(), md, 100.0 * ms);
    ASSERT_GT(dir_err.size(), rows.size() / 2);
    EXPECT_LT(md, 3.0);
    EXPECT_LT(ms, 0.10);
  }
}

// Sine at 60 km/h, direction 8 sin(2 pi 0.5 t): the FFT axis follows the sign.
TEST(ThesisSim, FftFollowsSineDirection) {
  const auto rows = run("sine", 1.0, "thesis-fft");
  std::vector<double> err;
  int sign_ok = 0;
  int sign_checked = 0;
  for (const Row& r : rows) {
    if (!r.est.has_direction || !r.truth.direction_deg) continue;
    err.push_back(std::abs(wrap_axis_deg(r.est.direction_deg - *r.truth.direction_deg)));
    if (std::abs(*r.truth.direction_deg) > 3.0) {
      ++sign_checked;
      if (r.est.direction_deg * *r.truth.direction_deg > 0.0) ++sign_ok;
    }
  }
  const double md = median(err);
  std::printf("sine 60 km/h: %zu/%zu frames with an axis; median |axis error| %.2f deg; sign right %d/%d\n",
              err.size(), rows.size(), md, sign_ok, sign_checked);
  ASSERT_GT(err.size(), rows.size() / 2);
  ASSERT_GT(sign_checked, 0);
  EXPECT_GT(sign_ok, sign_checked * 9 / 10);
  EXPECT_LT(md, 3.0);
}

// The overall system switches its direction source with its own Laplacian
// speed: mostly ORB at 5 km/h and FFT at 40 km/h ("const" scenario).
TEST(ThesisSim, CombinedSwitchesDirectionSourceAt15Kmh) {
  ASSERT_FALSE(thesis::fitted_laplacian_model().empty()) << "Laplacian model not fitted (run thesis_laplacian_fit)";
  const auto rows = run("const", 6.0, "thesis");
  int slow = 0;
  int slow_orb = 0;
  int fast = 0;
  int fast_fft = 0;
  for (const Row& r : rows) {
    const double kmh = mps_to_kmh(r.truth.speed_mps);
    const Method m = r.est.method;
    if (kmh > 4.0 && kmh < 6.0) {
      ++slow;
      if (m == Method::thesis_lap_orb) ++slow_orb;
    }
    if (kmh > 35.0 && kmh < 45.0) {
      ++fast;
      if (m == Method::thesis_lap_fft) ++fast_fft;
    }
  }
  std::printf("thesis: at 5 km/h %d/%d frames took direction from ORB; at 40 km/h %d/%d from the FFT\n", slow_orb,
              slow, fast_fft, fast);
  ASSERT_GT(slow, 10);
  ASSERT_GT(fast, 10);
  EXPECT_GT(slow_orb, slow / 2);
  EXPECT_GT(fast_fft, fast / 2);
}

}  // namespace
}  // namespace gvs::dsp
