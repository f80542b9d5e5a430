// gvs snapshot: one frame with what gvs makes of it, for checking focus,
// light and mounting: the frame with the ground-motion arrow (the blur axis
// with its sign; the car moves the opposite way over the ground), the
// numbers of the estimate and of the exposure, and the frame's windowed
// log-magnitude spectrum beside it (streaks show as a bright line through
// its centre at right angles to them; a sharp frame has energy far from the
// centre, a defocused one only near it).
//   gvs snapshot --dataset DIR [--frame N] --out FILE.png [--method gvs]
//   gvs snapshot --out FILE.png [--source URI] [--config gvsd.toml]   (live:
//     the configured source, e.g. libcamera; the last of a few frames)
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <fmt/format.h>
#include <opencv2/imgproc.hpp>

#include "commands.hpp"
#include "usage.hpp"
#include "live_source.hpp"
#include "gvs/dsp/frame_processor.hpp"
#include "gvs/drivers/dataset.hpp"
#include "gvs/drivers/png_file.hpp"
#include "gvs/dsp/frame_check.hpp"
#include "gvs/core/geometry.hpp"
#include "gvs/dsp/spectrum.hpp"
#include "gvs/dsp/thesis_fft.hpp"
#include "gvs/eval/speed_gaps.hpp"

namespace gvs::cli {

namespace {

struct SnapshotOptions {
  std::string dataset;     ///< empty: the live source
  std::string config_file;
  std::string source_uri;
  long frame = -1;  ///< position in frames.csv; -1 = the last
  std::string out;
  std::string method = "gvs";
};

/// log(1 + |F|) of the windowed frame, zero frequency in the centre, 0..255.
cv::Mat spectrum_image(const cv::Mat& gray) {
  dsp::WindowedSpectrum ws(gray.size());
  cv::Mat spectrum;
  ws.compute(gray, spectrum);
  cv::Mat planes[2];
  cv::split(spectrum, planes);
  cv::Mat mag;
  cv::magnitude(planes[0], planes[1], mag);
  mag += cv::Scalar::all(1.0);
  cv::log(mag, mag);
  // Zero frequency to the centre (the thesis FFT's quadrant swap; it takes
  // even sizes, so an odd last row or column is left out of the picture).
  cv::Mat shifted = mag(cv::Rect(0, 0, mag.cols & ~1, mag.rows & ~1)).clone();
  dsp::thesis::fft_shift(shifted);
  cv::Mat out;
  cv::normalize(shifted, out, 0, 255, cv::NORM_MINMAX, CV_8U);
  return out;
}

/// `text` cut into lines of at most `width` characters at spaces.
std::vector<std::string> wrap_words(const std::string& text, std::size_t width) {
  std::vector<std::string> lines;
  std::string line;
  std::size_t start = 0;
  while (start < text.size()) {
    std::size_t end = text.find(' ', start);
    if (end == std::string::npos) end = text.size();
    const std::string word = text.substr(start, end - start);
    if (!line.empty() && line.size() + 1 + word.size() > width) {
      lines.push_back(line);
      line.clear();
    }
    line += (line.empty() ? "" : " ") + word;
    start = end + 1;
  }
  if (!line.empty()) lines.push_back(line);
  return lines;
}

/// The frame with the estimate drawn on it, its spectrum beside it, and
/// below them the numbers and, without a speed, why (`why_no_speed`).
void draw_snapshot(const cv::Mat& gray, const core::VelocityEstimate& e, std::int64_t index,
                   const core::ExposurePlan& exposure, double mount_yaw_deg, const std::string& why_no_speed,
                   const std::string& out_file) {
  const dsp::FrameStats stats = dsp::measure_frame(gray);

  cv::Mat left;
  cv::cvtColor(gray, left, cv::COLOR_GRAY2BGR);
  cv::Mat right(gray.size(), CV_8UC3, cv::Scalar(0, 0, 0));
  const cv::Mat spectrum = spectrum_image(gray);
  cv::cvtColor(spectrum, right(cv::Rect(0, 0, spectrum.cols, spectrum.rows)), cv::COLOR_GRAY2BGR);
  const cv::Point2d centre(gray.cols / 2.0, gray.rows / 2.0);
  const double arm = 0.4 * std::min(gray.cols, gray.rows);
  if (e.has_direction) {
    // Ground motion in the image: a ground point moves by
    // (d_row, d_col) = (v_x, v_y) of the velocity in camera axes
    // (shared/spec/dataset-format.md); the car's own direction is opposite.
    const core::Vec2 v_cam = core::vehicle_to_camera({std::cos(core::deg_to_rad(e.direction_deg)),
                                                    std::sin(core::deg_to_rad(e.direction_deg))},
                                                   mount_yaw_deg);
    const cv::Point2d d(v_cam.y * arm, v_cam.x * arm);  // (x = col, y = row)
    cv::line(left, centre - d, centre + d, cv::Scalar(0, 200, 255), 1, cv::LINE_AA);  // blur axis
    cv::arrowedLine(left, centre, centre + d, cv::Scalar(0, 255, 0), 2, cv::LINE_AA, 0, 0.15);
  }
  // At 0.4 scale the Hershey font is about 7.5 px a character.
  const std::string why = why_no_speed.empty() ? std::string() : "no speed: " + why_no_speed;
  const std::vector<std::string> why_lines =
      why.empty() ? std::vector<std::string>{} : wrap_words(why, static_cast<std::size_t>(std::max(40, gray.cols * 2 / 8)));
  constexpr int kLinePx = 20;
  cv::Mat canvas(gray.rows + 64 + kLinePx * static_cast<int>(why_lines.size()), gray.cols * 2, CV_8UC3,
                 cv::Scalar(20, 20, 20));
  left.copyTo(canvas(cv::Rect(0, 0, gray.cols, gray.rows)));
  right.copyTo(canvas(cv::Rect(gray.cols, 0, gray.cols, gray.rows)));
  const std::string line1 =
      e.quality > 0.0
          ? fmt::format("frame {}  {}  speed {}  direction {}  yaw {}  quality {:.2f}", index,
                        core::method_word(e.method),
                        e.has_speed ? fmt::format("{:.2f} m/s", e.speed_mps) : std::string("-"),
                        e.has_direction ? fmt::format("{:+.2f} deg", e.direction_deg) : std::string("-"),
                        e.has_yaw_rate ? fmt::format("{:+.1f} deg/s", e.yaw_rate_dps) : std::string("-"), e.quality)
          : fmt::format("frame {}  no estimate: {}", index, core::method_word(e.method));
  const std::string line2 = fmt::format(
      "exposure {:.1f} us, {} pulse(s)   mean grey {:.0f}  contrast {:.1f}  saturated {:.1f} %   "
      "green: ground motion, orange: blur axis   right: spectrum",
      exposure.exposure_us, exposure.pulse_count, stats.mean_grey, stats.contrast_grey,
      100.0 * stats.saturated_fraction);
  cv::putText(canvas, line1, cv::Point(8, gray.rows + 24), cv::FONT_HERSHEY_SIMPLEX, 0.5, cv::Scalar(255, 255, 255),
              1, cv::LINE_AA);
  cv::putText(canvas, line2, cv::Point(8, gray.rows + 50), cv::FONT_HERSHEY_SIMPLEX, 0.4,
              cv::Scalar(200, 200, 200), 1, cv::LINE_AA);
  for (std::size_t i = 0; i < why_lines.size(); ++i) {
    cv::putText(canvas, why_lines[i], cv::Point(8, gray.rows + 50 + kLinePx * static_cast<int>(i + 1)),
                cv::FONT_HERSHEY_SIMPLEX, 0.4, cv::Scalar(120, 200, 255), 1, cv::LINE_AA);
  }
  const std::string error = drivers::write_png(out_file, canvas);
  if (!error.empty()) throw std::runtime_error(out_file + ": " + error);
  std::printf("%s\n%s\n%s%swrote %s\n", line1.c_str(), line2.c_str(), why.c_str(), why.empty() ? "" : "\n",
              out_file.c_str());
}

void snapshot_from_dataset(const SnapshotOptions& o) {
  const drivers::DatasetReader dataset(o.dataset);
  const auto n = static_cast<long>(dataset.frames().size());
  const long target = o.frame < 0 ? n - 1 : o.frame;
  if (target >= n) {
    throw std::runtime_error(o.dataset + ": --frame " + std::to_string(o.frame) + " but the dataset has " +
                             std::to_string(n) + " frames");
  }
  dsp::FrameProcessorConfig config;
  config.estimator.method = o.method;
  config.estimator.camera = dataset.camera().geometry;
  dsp::FrameProcessor processor(config);
  // The frames before it too: pair methods and the sign need the history.
  core::VelocityEstimate e;
  cv::Mat gray;
  for (long i = std::max(0L, target - 5); i <= target; ++i) {
    const drivers::FrameRecord& rec = dataset.frames()[static_cast<std::size_t>(i)];
    core::FrameView v;
    if (i < target) {
      // An unreadable frame before the one asked for costs history, not
      // the snapshot (as a dropped frame does in gvsd).
      try {
        gray = dataset.load_gray(static_cast<std::size_t>(i));
      } catch (const std::exception&) {
        continue;
      }
    } else {
      gray = dataset.load_gray(static_cast<std::size_t>(i));
    }
    v.gray = gray;
    v.index = rec.index;
    v.t_ns = rec.t_ns;
    v.exposure = rec.exposure;
    e = processor.process(v);
  }
  const drivers::FrameRecord& rec = dataset.frames()[static_cast<std::size_t>(target)];
  std::optional<drivers::TruthRecord> truth;
  for (const drivers::TruthRecord& t : dataset.truth()) {
    if (t.index == rec.index) truth = t;
  }
  const core::CameraGeometry& cam = dataset.camera().geometry;
  draw_snapshot(gray, e, rec.index, rec.exposure, cam.mount_yaw_deg, eval::why_no_speed(e, rec.exposure, cam, truth),
                o.out);
}

/// The live source: a few frames (pair methods and the sign need history), the last one drawn.
void snapshot_live(const SnapshotOptions& o) {
  LiveSource live = open_live_source(o.config_file, o.source_uri);
  dsp::FrameProcessorConfig config;
  config.estimator.method = o.method;
  config.estimator.camera = live.source->geometry();
  dsp::FrameProcessor processor(config);
  install_stop_signals();
  core::VelocityEstimate e;
  int frames = 0, errors = 0;
  while (frames < 6) {
    const drivers::SourceStatus st = live.source->next(live.slot, stop_requested());
    if (st == drivers::SourceStatus::stopped || st == drivers::SourceStatus::end) break;
    if (st == drivers::SourceStatus::error || live.slot.defect) {
      if (++errors > 100) break;
      continue;
    }
    e = processor.process(live.slot.view);
    ++frames;
  }
  if (frames == 0) {
    throw std::runtime_error("no frame from " + live.source->describe() + " (" + std::to_string(errors) +
                             " errors) " + live.source->health_text());
  }
  const core::CameraGeometry& cam = live.source->geometry();
  draw_snapshot(live.slot.view.gray, e, live.slot.view.index, live.slot.view.exposure, cam.mount_yaw_deg,
                eval::why_no_speed(e, live.slot.view.exposure, cam, std::nullopt), o.out);
}


}  // namespace

void register_snapshot(CLI::App& app) {
  auto opts = std::make_shared<SnapshotOptions>();
  CLI::App* cmd = app.add_subcommand(
      "snapshot", "One frame with its estimate drawn on it and its spectrum beside it (focus, light, mounting)");
  cmd->add_option("--dataset", opts->dataset, "gvs-dataset folder (a recording, or gvs sim's output)")
      ->check(CLI::ExistingDirectory);
  cmd->add_option("--source", opts->source_uri,
                  "Without --dataset: live source URI (default: the configuration's), e.g. libcamera, sim:sine");
  cmd->add_option("--config", opts->config_file, "Without --dataset: gvsd configuration (TOML)")
      ->check(CLI::ExistingFile);
  cmd->add_option("--frame", opts->frame, "Position in frames.csv (default: the last)");
  cmd->add_option("--out", opts->out, "PNG to write")->required();
  cmd->add_option("--method", opts->method, "Estimator: " + method_list())->check(method_check())->capture_default_str();
  cmd->callback([opts] {
    if (!opts->dataset.empty()) {
      snapshot_from_dataset(*opts);
    } else {
      snapshot_live(*opts);
    }
  });
}

}  // namespace gvs::cli
