// gvs sim: writes a simulated run as a gvs-dataset/1 folder, truth included.
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <map>
#include <memory>
#include <string>

#include <CLI/CLI.hpp>

#include "commands.hpp"
#include "usage.hpp"
#include "live_source.hpp"
#include "progress.hpp"
#include "gvs/dsp/frame_processor.hpp"
#include "gvs/drivers/dataset.hpp"
#include "gvs/drivers/simulator.hpp"
#include "gvs/dsp/exposure_control.hpp"

namespace gvs::cli {

namespace {

struct SimOptions {
  drivers::SimulatorConfig config;
  std::string out;
  std::string light = "normal";
  std::string exposure_mode = "fixed";
  std::string loop_method = "gvs";
  bool force = false;
  bool lasers = false;
  std::size_t laser_beams = 4;
};

namespace fs = std::filesystem;

/// The dataset is rendered into a hidden folder beside --out (same file
/// system, so the final rename is atomic); an interrupted or failed run
/// removes it and leaves --out as it was.
class StagingFolder {
 public:
  explicit StagingFolder(fs::path out) : out_(std::move(out)) {
    out_ = out_.lexically_normal();
    if (!out_.has_filename()) out_ = out_.parent_path();  // "run/" names the folder "run"
    const fs::path parent = out_.has_parent_path() ? out_.parent_path() : fs::path(".");
    path_ = parent / ("." + out_.filename().string() + ".partial-" + std::to_string(::getpid()));
    fs::remove_all(path_);
  }
  StagingFolder(const StagingFolder&) = delete;
  StagingFolder& operator=(const StagingFolder&) = delete;
  ~StagingFolder() {
    std::error_code ec;
    if (!committed_) fs::remove_all(path_, ec);
  }
  [[nodiscard]] const fs::path& path() const { return path_; }
  /// Replaces the --out folder (checked by check_out_folder) with the run.
  void commit() {
    if (fs::exists(out_)) fs::remove_all(out_);
    fs::rename(path_, out_);
    committed_ = true;
  }

 private:
  fs::path out_;
  fs::path path_;
  bool committed_ = false;
};

/// Refuses to mix a new run into an existing dataset unless told to replace it.
void check_out_folder(const SimOptions& o) {
  const fs::path out(o.out);
  if (!fs::exists(out)) return;
  if (!fs::is_directory(out)) throw std::runtime_error(o.out + ": exists and is not a folder; name a new folder for --out");
  if (!fs::is_empty(out) && !o.force) {
    throw std::runtime_error(o.out + ": exists and is not empty; name a new folder, or pass --force to replace it");
  }
}

void run_sim(const SimOptions& o) {
  drivers::SimulatorConfig config = o.config;
  static const std::map<std::string, drivers::LightLevel> lights = {
      {"normal", drivers::LightLevel::normal}, {"under", drivers::LightLevel::under}, {"over", drivers::LightLevel::over}};
  config.light = lights.at(o.light);
  if (o.lasers) config.lasers = core::design_laser_geometry(config.camera, config.camera_height_mm, o.laser_beams);

  check_out_folder(o);
  drivers::Simulator sim(config);
  drivers::CameraInfo camera;
  camera.geometry = config.camera;
  camera.ground = sim.config().ground;
  camera.height_mm = config.camera_height_mm;
  camera.lasers = config.lasers;
  camera.description = "gvs sim --scenario " + config.scenario + " --seed " + std::to_string(config.seed);
  if (config.body != "flat") camera.description += " --body " + config.body;
  if (camera.ground != "procedural") camera.description += " --ground " + camera.ground;
  if (o.lasers) camera.description += " --lasers" + (o.laser_beams == 4 ? std::string() : " --laser-beams 3");
  install_stop_signals();  // before the staging folder exists, so Ctrl-C always cleans it up
  StagingFolder staging(o.out);
  drivers::DatasetWriter writer(staging.path(), camera, /*with_truth=*/true,
                                /*with_body_pose=*/sim.has_body_motion());

  // Closed loop: the estimator measures each frame as gvsd would, and the
  // exposure controller plans the next frame's exposure from that estimate.
  dsp::ExposureMode mode = dsp::ExposureMode::fixed;
  dsp::parse_exposure_mode(o.exposure_mode.c_str(), mode);
  std::unique_ptr<dsp::FrameProcessor> loop;
  dsp::ExposureLimits limits;
  if (mode != dsp::ExposureMode::fixed) {
    dsp::FrameProcessorConfig pc;
    pc.estimator.method = o.loop_method;
    pc.estimator.camera = config.camera;
    pc.lasers = config.lasers;  // the dots masked out of what the loop's estimator sees
    pc.nominal_height_mm = config.camera_height_mm;
    loop = std::make_unique<dsp::FrameProcessor>(pc);
    limits = dsp::exposure_limits_for(config.camera, config.fps);
    limits.max_exposure_us = config.exposure_us;
  }

  drivers::SimFrame frame;
  std::size_t count = 0;
  const std::atomic<bool>& stop = stop_requested();
  auto progress = std::make_unique<Progress>("gvs sim", sim.frame_count());
  while (!stop.load() && sim.next(frame)) {
    writer.write_frame(frame.gray, frame.record);
    writer.write_truth(frame.truth);
    ++count;
    progress->update(count);
    if (loop) {
      core::FrameView view;
      view.gray = frame.gray;
      view.index = frame.record.index;
      view.t_ns = frame.record.t_ns;
      view.exposure = frame.record.exposure;
      const core::VelocityEstimate e = loop->process(view);
      sim.set_exposure(dsp::next_exposure(e, frame.record.exposure, mode, limits));
    }
  }
  progress.reset();
  writer.close();
  if (stop.load()) {
    std::fprintf(stderr, "gvs sim: interrupted after %zu frames; %s left as it was\n", count, o.out.c_str());
    throw Interrupted{};
  }
  staging.commit();
  std::printf("wrote %zu frames of scenario '%s'%s%s (exposure %s, ground %s) to %s\n", count,
              config.scenario.c_str(), config.body != "flat" ? " with body motion " : "",
              config.body != "flat" ? config.body.c_str() : "", o.exposure_mode.c_str(), camera.ground.c_str(),
              o.out.c_str());
}

/// What each scenario drives, for --help (drivers/src/sim/scenarios.cpp).
std::string scenario_help() {
  static const std::map<std::string, std::string> what = {
      {"const", "speeds 1 .. 140 km/h at a fixed direction of 10 deg, 1 s each (9 s)"},
      {"sine", "60 km/h, direction swinging +-8 deg at 0.5 Hz (10 s)"},
      {"accel", "standing 0.5 s, 0 -> 140 km/h in 6 s, 1 s at 140 km/h (7.5 s)"},
      {"brake", "100 km/h for 0.5 s, braking to a standstill in 2.5 s (peak 2.1 g), standing 1 s (4 s)"},
      {"skidpad", "skidpad circle, radius 9.125 m at 12 m/s turning left, -3 deg sideslip (8 s)"},
      {"crawl", "crawling 0.1 - 4 m/s with direction changes, reversing, a little yaw (10 s)"},
      {"stop", "standing still 2 s, then pulling away to 5 m/s within 2.5 s (6 s)"},
      {"spin", "sliding at 15 m/s while the car spins 180 deg CCW (5 s)"},
  };
  std::string text = "Scenario:";
  for (const std::string& n : drivers::scenario_names()) {
    const auto it = what.find(n);
    text += "\n  " + n + ": " + (it != what.end() ? it->second : "(see docs/simulator.md)");
  }
  return text;
}

}  // namespace

void register_sim(CLI::App& app) {
  auto opts = std::make_shared<SimOptions>();
  CLI::App* cmd = app.add_subcommand("sim", "Render a simulated run into a gvs-dataset/1 folder (with truth.csv)");
  cmd->add_option("--scenario", opts->config.scenario, scenario_help())
      ->required()
      ->check(CLI::IsMember(drivers::scenario_names()));
  cmd->add_option("--body", opts->config.body,
                  "Body motion over the scenario: flat (camera at its nominal 60 mm, level), heave (height "
                  "+-5 mm at 1.3, 2.9 and 4.7 Hz) or ride (heave, pitch 1 deg/g up to 1.5 deg and roll 0.75 "
                  "deg/g up to 1 deg from the scenario's accelerations, a kerb strike of 10 mm in 50 ms every 4 s "
                  "from 1.5 s); truth.csv then has height_mm, pitch_deg, roll_deg (docs/simulator.md)")
      ->check(CLI::IsMember(drivers::body_motion_names()))
      ->capture_default_str();
  cmd->add_option("--out", opts->out, "Dataset folder to write (created; an existing non-empty one needs --force)")
      ->required();
  cmd->add_flag("--force", opts->force, "Replace an existing dataset folder at --out");
  cmd->add_option("--seconds", opts->config.seconds, "Length of the run, s (default: the scenario's)")
      ->check(positive_number());
  cmd->add_option("--seed", opts->config.seed, "Texture and noise seed")
      ->check(seed_number())
      ->capture_default_str();
  cmd->add_option("--fps", opts->config.fps, "Frame rate, Hz")->check(number_in(1.0, 1000.0))->capture_default_str();
  cmd->add_option("--exposure-us", opts->config.exposure_us, "Continuous exposure, microseconds (with --exposure adaptive or double-pulse: the longest)")
      ->check(number_in(1.0, 100000.0))
      ->capture_default_str();
  cmd->add_option("--exposure", opts->exposure_mode,
                  "Exposure control: fixed (--exposure-us), adaptive (one strobe keeping the streak 10-80 px) or "
                  "double-pulse, closed loop through the estimator")
      ->check(CLI::IsMember({"fixed", "adaptive", "double-pulse"}))
      ->capture_default_str();
  cmd->add_option("--loop-method", opts->loop_method, "Estimator closing the exposure loop: " + method_list())
      ->check(method_check())
      ->capture_default_str();
  cmd->add_option("--light", opts->light, "Scene brightness: normal, under (mean grey ~10), over (~15 % saturated)")
      ->check(CLI::IsMember({"normal", "under", "over"}))
      ->capture_default_str();
  cmd->add_option("--ground", opts->config.ground,
                  "Ground: procedural (the simulated asphalt) or photo:FILE[:MM_PER_PIXEL], a seamless square "
                  "grey photo at MM_PER_PIXEL (default 0.2) laid in randomised, blended tiles")
      ->capture_default_str();
  cmd->add_flag("--lasers", opts->lasers,
                "Laser dots: the design's four beams at 45 deg (docs/hardware.md, \"Laser dots\"), lit with the "
                "LED; their geometry goes into camera.json");
  cmd->add_option("--laser-beams", opts->laser_beams,
                  "With --lasers: 4 (the design), or 3 (the plane without the fourth beam's check)")
      ->check(CLI::IsMember({3, 4}))
      ->capture_default_str();
  cmd->add_option("--laser-brightness", opts->config.laser_peak_relative,
                  "Laser dots' peak irradiance over the LED ring's")
      ->check(number_in(0.0, 100.0))
      ->capture_default_str();
  cmd->add_option("--width", opts->config.camera.width_px, "Image width, px")->check(whole_number_in(16, 4096));
  cmd->add_option("--height", opts->config.camera.height_px, "Image height, px")->check(whole_number_in(16, 4096));
  cmd->add_option("--mm-per-px", opts->config.camera.mm_per_px, "Ground resolution, mm per pixel")->check(number_in(0.01, 10.0));
  cmd->add_option("--mount-yaw-deg", opts->config.camera.mount_yaw_deg, "Camera yaw on the car, CCW from above")
      ->check(number_in(-180.0, 180.0));
  cmd->callback([opts] { run_sim(*opts); });
}

}  // namespace gvs::cli
