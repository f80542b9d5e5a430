// gvs_sim_eval: scores the gvs estimator on a simulated run (the figures in
// docs/estimator.md).
//   gvs_sim_eval <scenario> [fixed|adaptive|double-pulse] [normal|under|over] [seconds] [-v]
#include <cstdlib>
#include <cstring>
#include <string>

#include "gvs_sim_eval.hpp"

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: %s <scenario> [fixed|adaptive|double-pulse] [normal|under|over] [seconds] [-v]\n", argv[0]);
    return 2;
  }
  gvs::drivers::SimulatorConfig cfg;
  cfg.scenario = argv[1];
  gvs::dsp::ExposureMode mode = gvs::dsp::ExposureMode::fixed;
  if (argc > 2 && !gvs::dsp::parse_exposure_mode(argv[2], mode)) {
    std::fprintf(stderr, "exposure mode must be fixed, adaptive or double-pulse\n");
    return 2;
  }
  if (argc > 3) {
    const std::string l = argv[3];
    cfg.light = l == "under" ? gvs::drivers::LightLevel::under
                : l == "over" ? gvs::drivers::LightLevel::over
                              : gvs::drivers::LightLevel::normal;
  }
  if (argc > 4) cfg.seconds = std::atof(argv[4]);
  const bool verbose = argc > 5 && std::strcmp(argv[5], "-v") == 0;
  const gvs::test::RunScore s = gvs::test::run_and_score(cfg, mode, 0.0, verbose);
  const std::string title = cfg.scenario + " " + (argc > 2 ? argv[2] : "fixed") + " " + (argc > 3 ? argv[3] : "normal");
  gvs::test::print_score(title.c_str(), s);
  return 0;
}
