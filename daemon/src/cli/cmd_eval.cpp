// gvs eval: accuracy of an estimates CSV against a dataset's truth, per speed
// band; optionally a plot (drawn by gvs_plot.py on Debian's matplotlib).
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <memory>
#include <string>
#include <unordered_map>

#include <CLI/CLI.hpp>

#include "commands.hpp"
#include "gvs/eval/accuracy.hpp"
#include "gvs/eval/height_error.hpp"
#include "gvs/eval/ride_error.hpp"
#include "gvs/eval/speed_gaps.hpp"
#include "gvs/drivers/dataset.hpp"
#include "gvs/drivers/estimates_csv.hpp"

namespace gvs::cli {

namespace fs = std::filesystem;

namespace {

struct EvalOptions {
  std::string dataset;
  std::string estimates;
  std::string plot;
  std::string json;
  std::string title;
  std::string ride;
};

/// Where gvs_plot.py is: $GVS_PLOT_SCRIPT, the installed copy beside this
/// executable (<prefix>/bin/gvs -> <prefix>/share/gvs/), or the source tree.
fs::path plot_script() {
  if (const char* env = std::getenv("GVS_PLOT_SCRIPT")) return env;
  std::error_code ec;
  const fs::path installed = fs::read_symlink("/proc/self/exe", ec).parent_path().parent_path() / GVS_PLOT_SCRIPT_INSTALLED;
  for (const fs::path& p : {installed, fs::path(GVS_PLOT_SCRIPT_SOURCE)}) {
    if (fs::exists(p)) return p;
  }
  throw std::runtime_error(std::string("gvs_plot.py not found at ") + GVS_PLOT_SCRIPT_SOURCE + " or " +
                           installed.string() + "; set GVS_PLOT_SCRIPT");
}

std::string shell_quote(const std::string& s) {
  std::string q = "'";
  for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

void write_joined_csv(const fs::path& file, const std::vector<drivers::TruthRecord>& truth,
                      const std::vector<drivers::EstimateRow>& estimates) {
  std::unordered_map<std::int64_t, const drivers::EstimateRow*> by_index;
  for (const auto& r : estimates) by_index[r.estimate.index] = &r;
  std::ofstream out(file);
  if (!out) throw std::runtime_error(file.string() + ": cannot write the plot data");
  out << "t_s,truth_speed_mps,truth_direction_deg,truth_yaw_rate_dps,speed_mps,direction_deg,yaw_rate_dps,quality\n";
  const double t0 = truth.empty() ? 0.0 : static_cast<double>(truth.front().t_ns) * 1e-9;
  for (const auto& t : truth) {
    out << static_cast<double>(t.t_ns) * 1e-9 - t0 << ',' << t.speed_mps << ',';
    if (t.direction_deg) out << *t.direction_deg;
    out << ',' << t.yaw_rate_dps << ',';
    const auto it = by_index.find(t.index);
    if (it != by_index.end()) {
      const core::VelocityEstimate& e = it->second->estimate;
      if (e.has_speed) out << e.speed_mps;
      out << ',';
      if (e.has_direction) out << e.direction_deg;
      out << ',';
      if (e.has_yaw_rate) out << e.yaw_rate_dps;
      out << ',' << e.quality;
    } else {
      out << ",,,0";
    }
    out << '\n';
  }
}

void run_eval(const EvalOptions& o) {
  const drivers::DatasetReader dataset(o.dataset);
  if (!dataset.has_truth()) {
    throw drivers::DatasetError((fs::path(o.dataset) / "truth.csv").string() +
                                ": missing; gvs eval needs ground truth (gvs sim writes it)");
  }
  const auto estimates = drivers::read_estimates_csv(o.estimates);
  const eval::AccuracyReport report = eval::evaluate_accuracy(dataset.truth(), estimates);
  std::printf("%s", eval::format_accuracy_table(report).c_str());
  // A run with body motion: the speed error against the camera's height
  // (camera.json's nominal height; 60 mm, the design's, when it has none).
  if (const auto height = eval::evaluate_speed_vs_height(dataset.truth(), estimates,
                                                         dataset.camera().height_mm.value_or(60.0))) {
    std::printf("%s", eval::format_height_table(*height).c_str());
  }
  if (!o.ride.empty()) {
    const auto rides = eval::read_ride_csv(o.ride);
    std::printf("%s", eval::format_ride_table(eval::evaluate_ride(dataset.truth(), rides, estimates,
                                                                  dataset.camera().height_mm.value_or(60.0)))
                          .c_str());
  }
  const std::string speed_gaps = eval::format_speed_gaps(eval::find_speed_gaps(dataset, estimates));
  std::printf("%s", speed_gaps.c_str());
  if (!o.json.empty()) {
    std::ofstream out(o.json);
    if (!out) throw std::runtime_error(o.json + ": cannot write");
    out << eval::format_accuracy_json(report) << '\n';
  }
  if (!o.plot.empty()) {
    const fs::path joined = fs::path(o.plot).replace_extension(".plotdata.csv");
    write_joined_csv(joined, dataset.truth(), estimates);
    const std::string title = o.title.empty() ? fs::path(o.dataset).filename().string() : o.title;
    const std::string cmd = "/usr/bin/python3 " + shell_quote(plot_script().string()) + " " +
                            shell_quote(joined.string()) + " " + shell_quote(o.plot) + " " + shell_quote(title) +
                            (speed_gaps.empty() ? std::string() : " --speed-note " + shell_quote(speed_gaps));
    const int rc = std::system(cmd.c_str());
    std::error_code ignore;
    fs::remove(joined, ignore);
    if (rc != 0) {
      throw std::runtime_error("plotting failed (" + cmd + "); is python3-matplotlib installed under /usr/bin/python3?");
    }
    std::printf("plot written to %s\n", o.plot.c_str());
  }
}

}  // namespace

void register_eval(CLI::App& app) {
  auto opts = std::make_shared<EvalOptions>();
  CLI::App* cmd = app.add_subcommand("eval", "Accuracy of an estimates CSV against a dataset's truth, per speed band");
  cmd->add_option("dataset", opts->dataset, "gvs-dataset/1 folder with truth.csv")->required()->check(CLI::ExistingDirectory);
  cmd->add_option("estimates", opts->estimates, "Estimates CSV (from gvs replay)")->required()->check(CLI::ExistingFile);
  cmd->add_option("--plot", opts->plot, "Draw direction, speed and yaw rate against the truth, their error histograms and why speeds are missing into this PNG");
  cmd->add_option("--title", opts->title, "Plot title (default: the dataset folder's name)");
  cmd->add_option("--ride", opts->ride, "Ride-height CSV (gvs replay --ride): height, pitch and roll error against the truth")
      ->check(CLI::ExistingFile);
  cmd->add_option("--json", opts->json, "Also write the figures as JSON");
  cmd->callback([opts] { run_eval(*opts); });
}

}  // namespace gvs::cli
