// gvs: the offline and bench tool (simulate, replay, evaluate, ...).
#include <cstdio>
#include <exception>

#include <CLI/CLI.hpp>

#include "commands.hpp"
#include "gvs/daemon/logging.hpp"
#include "gvs/drivers/camera_device.hpp"
#include "gvs/dsp/thesis_orb_methods.hpp"
#include "usage.hpp"

int main(int argc, char** argv) {
  // The desk tool has every method, the thesis's ORB ones too (gvsd has not).
  gvs::dsp::add_thesis_orb_estimators();
  CLI::App app{"gvs: ground velocity sensor tools (simulate, replay, evaluate, monitor, calibrate, snapshot, record)",
               "gvs"};
  app.set_version_flag("--version", gvs::cli::version_text("gvs"), "Print the version and the git commit, then exit");
  app.require_subcommand(1);
  app.footer(
      "Each command's options: gvs COMMAND --help.\n"
      "Exit status: 0 done; 1 the work failed (the message says why); 2 bad command line; 130 gvs sim interrupted.\n"
      "Documentation: README.md and docs/ in the source, /usr/share/doc/gvs/ in the Debian package; man gvs, man gvsd.");
  gvs::cli::register_sim(app);
  gvs::cli::register_replay(app);
  gvs::cli::register_eval(app);
  gvs::cli::register_monitor(app);
  gvs::cli::register_calibrate(app);
  gvs::cli::register_snapshot(app);
  gvs::cli::register_record(app);
  if (!gvs::cli::check_subcommands(app, argc, argv)) return gvs::cli::kUsageExitCode;
  gvs::daemon::silence_library_logs();
  // libcamera's warnings and errors as gvs lines; its information lines off.
  gvs::drivers::route_camera_library_log([](std::string_view level, std::string_view message) {
    if (level == "DEBUG" || level == "INFO") return;
    std::fprintf(stderr, "gvs: libcamera %s: %.*s\n", level == "WARN" ? "warning" : "error",
                 static_cast<int>(message.size()), message.data());
  });
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return gvs::cli::usage_exit(app, e);
  } catch (const gvs::cli::Interrupted&) {
    return 130;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "gvs: error: %s\n", gvs::daemon::describe_exception(e).c_str());
    return 1;
  }
  return 0;
}
