// gvs record: a gvs-dataset/1 from a live source (shared/spec/dataset-format.md),
// so a run on the car can be replayed and evaluated on a desk.
//   gvs record --out DIR [--seconds S] [--config gvsd.toml] [--source URI]
// Each frame is written with the exposure the camera actually applied (the
// libcamera source takes it from the request's metadata) and its start-of-
// exposure time; frames the source could not deliver whole are left out and
// show as index gaps. The exposure stays at [exposure] initial_us (no closed
// loop while recording). A simulated source (sim:) also writes truth.csv, so
// the recorder itself can be checked with gvs replay + gvs eval.
#include <cstdio>
#include <filesystem>
#include <memory>
#include <stdexcept>
#include <string>

#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include "commands.hpp"
#include "gvs/daemon/clock.hpp"
#include "gvs/drivers/dataset.hpp"
#include "live_source.hpp"

namespace gvs::cli {

namespace {

struct RecordOptions {
  std::string out;
  double seconds = 10.0;
  std::string config_file;
  std::string source_uri;
};

void run_record(const RecordOptions& o) {
  if (std::filesystem::exists(o.out) && !std::filesystem::is_empty(o.out)) {
    throw std::runtime_error(o.out + ": exists and is not empty; name a new folder for the recording");
  }
  LiveSource live = open_live_source(o.config_file, o.source_uri);
  drivers::CameraInfo camera;
  camera.geometry = live.source->geometry();
  camera.description = "gvs record from " + live.source->describe();
  const bool simulated = live.config.source_uri.rfind("sim:", 0) == 0;  // the simulator knows its truth
  drivers::DatasetWriter writer(o.out, camera, simulated);
  std::fprintf(stderr, "recording %s for %.1f s into %s (Ctrl-C stops)\n", live.source->describe().c_str(),
               o.seconds, o.out.c_str());
  install_stop_signals();

  const std::int64_t end_ns = daemon::mono_now_ns() + static_cast<std::int64_t>(o.seconds * 1e9);
  std::int64_t first_index = -1;
  long written = 0, defects = 0, errors = 0;
  std::atomic<bool>& stop = stop_requested();
  while (daemon::mono_now_ns() < end_ns && !stop.load()) {
    const daemon::SourceStatus st = live.source->next(live.slot, stop);
    if (st == daemon::SourceStatus::stopped || st == daemon::SourceStatus::end) break;
    if (st == daemon::SourceStatus::error) {
      ++errors;
      continue;
    }
    if (live.slot.defect != nullptr) {  // no pixels or no trustworthy exposure: a gap, not a lie
      ++defects;
      continue;
    }
    if (first_index < 0) first_index = live.slot.view.index;
    drivers::FrameRecord rec;
    rec.index = live.slot.view.index - first_index;
    rec.t_ns = live.slot.view.t_ns;
    rec.exposure = live.slot.view.exposure;
    writer.write_frame(live.slot.view.gray, rec);
    if (simulated && live.slot.truth.known) {
      const daemon::FrameTruth& t = live.slot.truth;
      drivers::TruthRecord truth;
      truth.index = rec.index;
      truth.t_ns = rec.t_ns + static_cast<std::int64_t>(rec.exposure.light_centre_us() * 1000.0);
      truth.vx_mps = t.vx_mps;
      truth.vy_mps = t.vy_mps;
      truth.speed_mps = t.speed_mps;
      if (t.speed_mps >= 0.01) truth.direction_deg = t.direction_deg;
      truth.yaw_rate_dps = t.yaw_rate_dps;
      writer.write_truth(truth);
    }
    ++written;
  }
  writer.close();
  const std::string health = live.source->health_text();
  std::printf("recorded %ld frames into %s (%ld left out as defective, %ld source errors)%s%s\n", written,
              o.out.c_str(), defects, errors, health.empty() ? "" : "\n", health.c_str());
  if (written == 0) throw std::runtime_error("no frame recorded from " + live.source->describe());
}

}  // namespace

void register_record(CLI::App& app) {
  auto opts = std::make_shared<RecordOptions>();
  CLI::App* cmd = app.add_subcommand("record", "Record a gvs-dataset from the live camera (applied exposure, timestamps)");
  cmd->add_option("--out", opts->out, "Dataset folder to create")->required();
  cmd->add_option("--seconds", opts->seconds, "How long to record")->capture_default_str()->check(CLI::Range(0.01, 86400.0));
  cmd->add_option("--config", opts->config_file, "gvsd configuration (TOML): source, camera, [libcamera], exposure")
      ->check(CLI::ExistingFile);
  cmd->add_option("--source", opts->source_uri, "Source URI, overrides the configuration: libcamera[:ID], sim:SCENARIO");
  cmd->callback([opts] { run_record(*opts); });
}

}  // namespace gvs::cli
