// gvs replay: runs the daemon's estimator over every frame of a dataset and
// writes the estimates CSV of shared/spec/dataset-format.md.
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "commands.hpp"
#include "progress.hpp"
#include "usage.hpp"
#include "gvs/daemon/config.hpp"
#include "gvs/eval/replay.hpp"
#include "gvs/eval/ride_error.hpp"
#include "gvs/eval/speed_gaps.hpp"
#include "gvs/drivers/dataset.hpp"
#include "gvs/drivers/estimates_csv.hpp"

namespace gvs::cli {

namespace {

struct ReplayCliOptions {
  std::string dataset;
  std::string out;
  std::string config_file;
  std::string method;
  bool timing = false;
  std::string ride_out;
  bool no_lasers = false;
  bool no_scale_correction = false;
};

void run_replay(const ReplayCliOptions& o) {
  const drivers::DatasetReader dataset(o.dataset);
  dsp::FrameProcessorConfig config;
  if (!o.config_file.empty()) {
    // The estimator settings of a gvsd configuration; the camera geometry
    // stays the dataset's own (camera.json describes the frames).
    config.estimator.method = daemon::load_config_file(o.config_file).estimator_method;
  }
  if (!o.method.empty()) config.estimator.method = o.method;

  drivers::EstimatesCsvWriter writer(o.out);
  eval::ReplayOptions options;
  options.time_reference_dft = o.timing;
  options.stage_pairs = o.timing ? 8 : 0;
  options.use_dataset_lasers = !o.no_lasers;
  config.correct_scale = !o.no_scale_correction;
  // The estimates CSV's columns are fixed (shared/spec/dataset-format.md):
  // the measured ride height goes to a file of its own.
  std::unique_ptr<eval::RideCsvWriter> ride;
  if (!o.ride_out.empty()) {
    ride = std::make_unique<eval::RideCsvWriter>(o.ride_out);
    options.dots_sink = [&ride](const core::VelocityEstimate& e, const dsp::LaserDotResult& dots) {
      ride->write(e, static_cast<int>(dots.found));
    };
  }
  std::size_t done = 0;
  std::size_t with_speed = 0;
  std::vector<drivers::EstimateRow> rows;  // for saying why speeds are missing
  auto progress = std::make_unique<Progress>("gvs replay", dataset.frames().size());
  const eval::ReplayStats stats = eval::replay_dataset(
      dataset, config,
      [&](const core::VelocityEstimate& e) {
        writer.write(e);
        if (e.has_speed) ++with_speed;
        if (dataset.has_truth()) rows.push_back({e});
        progress->update(++done);
      },
      options);
  progress.reset();
  writer.close();
  if (ride) ride->close();
  std::printf("replayed %zu frames with '%s': %zu with an estimate, %zu with a speed; wrote %s\n", stats.frames,
              config.estimator.method.c_str(), stats.with_estimate, with_speed, o.out.c_str());
  if (dataset.has_truth()) std::printf("%s", eval::format_speed_gaps(eval::find_speed_gaps(dataset, rows)).c_str());
  if (o.timing && stats.frames > 0) {
    const double n = static_cast<double>(stats.frames);
    std::printf("timing per frame: decode PNG %.3f ms, estimator %.3f ms, one forward DFT %.3f ms; "
                "replay / (decode + DFT) = %.2f\n",
                stats.decode_s / n * 1e3, stats.estimate_s / n * 1e3, stats.dft_s / n * 1e3,
                (stats.decode_s + stats.estimate_s) / (stats.decode_s + stats.dft_s));
    // The benchmark's per-stage table (tests/dsp/gvs_stage_bench.cpp), on this dataset's frames.
    std::printf("stages alone, CPU per call on %zu frame pairs of the run (as gvs_estimator_bench's BM_Stage):\n",
                stats.stage_pairs);
    for (const eval::StageTime& t : stats.stages) {
      std::printf("  %-32s %7.3f ms  %s\n", t.name.c_str(), t.cpu_ms, t.description.c_str());
    }
  }
}

}  // namespace

void register_replay(CLI::App& app) {
  auto opts = std::make_shared<ReplayCliOptions>();
  CLI::App* cmd = app.add_subcommand("replay", "Run the estimator over every frame of a dataset; write estimates CSV");
  cmd->add_option("dataset", opts->dataset, "gvs-dataset/1 folder")->required()->check(CLI::ExistingDirectory);
  cmd->add_option("--out", opts->out, "Estimates CSV to write")->required();
  cmd->add_option("--config", opts->config_file, "gvsd configuration (TOML) to take the estimator settings from")
      ->check(CLI::ExistingFile);
  cmd->add_option("--method", opts->method, "Estimator (overrides the configuration; default gvs): " + method_list())
      ->check(method_check());
  cmd->add_option("--ride", opts->ride_out,
                  "Also write the ride height measured by the laser dots (height_mm, pitch_deg, roll_deg) to this "
                  "CSV (the estimates CSV has no room for it)");
  cmd->add_flag("--no-lasers", opts->no_lasers, "Ignore camera.json's laser dots (no masking, no height)");
  cmd->add_flag("--no-scale-correction", opts->no_scale_correction,
                "Find and mask the dots, but keep the speed at the nominal scale (to measure the correction)");
  cmd->add_flag("--timing", opts->timing,
                "Also time PNG decoding and one forward DFT per frame, and compare; then each estimator stage "
                "alone on 8 frame pairs of the run");
  cmd->callback([opts] { run_replay(*opts); });
}

}  // namespace gvs::cli
