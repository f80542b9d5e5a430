// gvs calibrate: fits the sensor to a car and writes the result into the
// gvsd configuration ([camera] mm_per_px, mount_yaw_deg).
//   gvs calibrate scale FRAME.png --inner-corners 9x6 --square-mm 10 [--config gvsd.toml]
//   gvs calibrate yaw DATASET [--min-speed-kmh 5] [--method gvs] [--config gvsd.toml]
//   gvs calibrate height --at 50:DATASET --at 60:DATASET ... [--out lasers.json]
// `scale`: a frame of a printed checkerboard lying flat under the sensor.
// `yaw`: a recording (gvs record, or any gvs-dataset) of driving straight
// ahead; its camera.json's mount_yaw_deg is what the estimates were made with.
// `height`: recordings of the head on spacer blocks; the laser dots' beams.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "commands.hpp"
#include "usage.hpp"
#include "gvs/daemon/config_edit.hpp"
#include "gvs/eval/replay.hpp"
#include "gvs/dsp/checkerboard.hpp"
#include "gvs/drivers/dataset.hpp"
#include "gvs/drivers/png_file.hpp"
#include "gvs/dsp/calibration.hpp"
#include "gvs/dsp/laser_calibration.hpp"

namespace gvs::cli {

namespace {

struct ScaleOptions {
  std::string image;
  std::string inner_corners = "9x6";
  double square_mm = 10.0;
  std::string config;
  bool create_config = false;
};

struct HeightOptions {
  std::vector<std::string> at;  ///< HEIGHT_MM:DATASET
  double exit_z_mm = -20.0;
  std::string out;
};

struct YawOptions {
  std::string dataset;
  double min_speed_kmh = 5.0;
  std::string method = "gvs";
  std::string config;
  bool create_config = false;
};

/// A mistyped --config would otherwise become a new file holding one key
/// while gvsd keeps reading the real one; creating it has to be asked for.
/// Checked before the measurement so a long fit is not wasted.
void check_config_target(const std::string& config, bool create) {
  if (config.empty() || create || std::filesystem::exists(config)) return;
  throw std::runtime_error(config + ": no such configuration file; check the path (gvsd reads "
                           "/etc/gvsd/gvsd.toml on the car), or pass --create-config to start a new file");
}

cv::Size parse_inner(const std::string& text) {
  int cols = 0;
  int rows = 0;
  char x = 0;
  if (std::sscanf(text.c_str(), "%d%c%d", &cols, &x, &rows) != 3 || (x != 'x' && x != 'X') || cols < 2 || rows < 2) {
    throw std::runtime_error("--inner-corners '" + text + "': give COLSxROWS of inner corners, e.g. 9x6 for a board of 10x7 squares");
  }
  return {cols, rows};
}

void run_scale(const ScaleOptions& o) {
  check_config_target(o.config, o.create_config);
  const cv::Size inner = parse_inner(o.inner_corners);
  const drivers::PngRead png = drivers::read_png(o.image, drivers::PngPixels::grey);
  if (png.pixels.empty()) throw std::runtime_error(o.image + ": " + png.error + " (give the frame as a PNG)");
  const cv::Mat& gray = png.pixels;
  const auto m = dsp::measure_checkerboard(gray, inner, o.square_mm);
  if (!m) {
    throw std::runtime_error(o.image + ": no checkerboard of " + o.inner_corners +
                             " inner corners found; is the whole board in view, lit and in focus?");
  }
  const dsp::GridScale& g = m->scale;
  std::printf("checkerboard %dx%d inner corners, squares %.3f mm\n", inner.width, inner.height, o.square_mm);
  std::printf("spacing along rows %.3f px, along columns %.3f px (spread %.2f %%), board rotated %.2f deg\n",
              g.spacing_along_rows_px, g.spacing_along_cols_px, g.spacing_spread_pct, g.grid_rotation_deg);
  std::printf("mm_per_px = %.6f\n", g.mm_per_px);
  if (std::abs(g.anisotropy_pct) > 1.0) {
    std::printf("warning: rows and columns differ by %.1f %%: the camera does not look straight down, or the "
                "board is not flat\n", g.anisotropy_pct);
  }
  if (!o.config.empty()) {
    daemon::set_config_numbers_in_file(o.config, "camera", {{"mm_per_px", g.mm_per_px}});
    std::printf("wrote [camera] mm_per_px to %s\n", o.config.c_str());
  }
}

void run_yaw(const YawOptions& o) {
  check_config_target(o.config, o.create_config);
  const drivers::DatasetReader dataset(o.dataset);
  dsp::FrameProcessorConfig config;
  config.estimator.method = o.method;
  std::vector<double> directions;
  const double min_mps = o.min_speed_kmh / 3.6;
  eval::replay_dataset(dataset, config, [&](const core::VelocityEstimate& e) {
    if (e.has_direction && (!e.has_speed || e.speed_mps >= min_mps)) directions.push_back(e.direction_deg);
  });
  const double configured = dataset.camera().geometry.mount_yaw_deg;
  const auto fit = dsp::fit_mount_yaw(directions, configured);
  if (!fit) {
    throw std::runtime_error(o.dataset + ": only " + std::to_string(directions.size()) +
                             " frames with a direction; record at least 20 frames of straight driving");
  }
  std::printf("%zu frames of %zu with a direction; median direction %+.3f deg, robust spread %.3f deg\n",
              fit->frames, dataset.frames().size(), fit->median_direction_deg, fit->spread_deg);
  std::printf("recorded with mount_yaw_deg = %.3f; mount_yaw_deg = %.3f\n", configured, fit->mount_yaw_deg);
  if (fit->spread_deg > 2.0) {
    std::printf("warning: directions spread by %.1f deg: was the car really driving straight?\n", fit->spread_deg);
  }
  if (!o.config.empty()) {
    daemon::set_config_numbers_in_file(o.config, "camera", {{"mount_yaw_deg", fit->mount_yaw_deg}});
    std::printf("wrote [camera] mount_yaw_deg to %s\n", o.config.c_str());
  }
}

void run_height(const HeightOptions& o) {
  if (o.at.size() < 2) throw std::runtime_error("--at: give at least two heights, e.g. --at 50:spacer50 --at 70:spacer70");
  std::vector<dsp::HeightObservation> observations;
  core::CameraGeometry camera;
  double nominal_mm = 60.0;
  core::LaserGeometry prior;
  for (std::size_t i = 0; i < o.at.size(); ++i) {
    const std::string& spec = o.at[i];
    const auto colon = spec.find(':');
    char* end = nullptr;
    const double h = colon == std::string::npos ? 0.0 : std::strtod(spec.c_str(), &end);
    if (colon == std::string::npos || end != spec.c_str() + colon || !(h > 0.0))
      throw std::runtime_error("--at '" + spec + "': give HEIGHT_MM:DATASET, e.g. 55:spacer55");
    const drivers::DatasetReader dataset(spec.substr(colon + 1));
    if (i == 0) {
      camera = dataset.camera().geometry;
      nominal_mm = dataset.camera().height_mm.value_or(60.0);
      prior = dataset.camera().lasers.enabled() ? dataset.camera().lasers
                                                : core::design_laser_geometry(camera, nominal_mm);
    }
    // Every frame of the height: the spots of each, as observations of that height.
    const double sigma_px = std::hypot(prior.spot_sigma_mm / camera.mm_per_px, 0.5) * 1.2;
    for (std::size_t f = 0; f < dataset.frames().size(); ++f) {
      observations.push_back({h, dsp::find_bright_spots(dataset.load_gray(f), sigma_px, prior.count + 2)});
    }
  }
  const auto fit = dsp::fit_laser_geometry(observations, camera, nominal_mm, prior, o.exit_z_mm);
  if (!fit) {
    throw std::runtime_error("not every dot was seen at two heights or more; are the lasers on, the plate flat and "
                             "the dots within 60 px of where camera.json (or the design) puts them?");
  }
  std::printf("%zu frames at %zu heights; ground points off their beams by %.4f mm RMS\n", observations.size(),
              o.at.size(), fit->rms_residual_mm);
  std::printf("beam    x_mm     y_mm     z_mm  azimuth_deg  tilt_deg\n");
  for (std::size_t k = 0; k < fit->lasers.count; ++k) {
    const core::LaserBeam& b = fit->lasers.beams[k];
    std::printf("%4zu %8.3f %8.3f %8.2f %12.3f %9.3f\n", k, b.x_mm, b.y_mm, b.z_mm, b.azimuth_deg, b.tilt_deg);
  }
  const std::string json = drivers::laser_geometry_json_text(fit->lasers);
  if (!o.out.empty()) {
    std::ofstream out(o.out);
    if (!out) throw std::runtime_error(o.out + ": cannot write");
    out << json << '\n';
    std::printf("wrote the \"lasers\" object for camera.json to %s\n", o.out.c_str());
  } else {
    std::printf("camera.json \"lasers\": %s\n", json.c_str());
  }
}

}  // namespace

void register_calibrate(CLI::App& app) {
  CLI::App* cmd = app.add_subcommand("calibrate", "Fit the sensor to the car: ground scale and mounting yaw");
  cmd->require_subcommand(1);

  auto scale = std::make_shared<ScaleOptions>();
  CLI::App* s = cmd->add_subcommand("scale", "mm_per_px from a frame of a printed checkerboard lying under the sensor");
  s->add_option("image", scale->image, "Frame (PNG) showing the whole board")->required()->check(CLI::ExistingFile);
  s->add_option("--inner-corners", scale->inner_corners, "Inner corners, COLSxROWS")->capture_default_str();
  s->add_option("--square-mm", scale->square_mm, "Measured size of one square, mm")
      ->check(number_in(0.1, 1000.0))->capture_default_str();
  s->add_option("--config", scale->config, "gvsd configuration to write [camera] mm_per_px into (must exist)");
  s->add_flag("--create-config", scale->create_config, "Create the --config file if it does not exist");
  s->callback([scale] { run_scale(*scale); });

  auto height = std::make_shared<HeightOptions>();
  CLI::App* h = cmd->add_subcommand(
      "height", "Laser dots' geometry from frames at known heights (the head on spacer blocks over a flat plate)");
  h->add_option("--at", height->at, "HEIGHT_MM:DATASET, one per spacer (at least two)")->required();
  h->add_option("--exit-z-mm", height->exit_z_mm, "Height of the beams' exit window relative to the optical centre, mm")
      ->capture_default_str();
  h->add_option("--out", height->out, "Write the \"lasers\" object (camera.json) to this file");
  h->callback([height] { run_height(*height); });

  auto yaw = std::make_shared<YawOptions>();
  CLI::App* y = cmd->add_subcommand("yaw", "mount_yaw_deg from a recording of driving straight ahead");
  y->add_option("dataset", yaw->dataset, "gvs-dataset folder")->required()->check(CLI::ExistingDirectory);
  y->add_option("--min-speed-kmh", yaw->min_speed_kmh, "Ignore slower frames")
      ->check(number_in(0.0, 500.0))
      ->capture_default_str();
  y->add_option("--method", yaw->method, "Estimator: " + method_list())->check(method_check())->capture_default_str();
  y->add_option("--config", yaw->config, "gvsd configuration to write [camera] mount_yaw_deg into (must exist)");
  y->add_flag("--create-config", yaw->create_config, "Create the --config file if it does not exist");
  y->callback([yaw] { run_yaw(*yaw); });
}

}  // namespace gvs::cli
