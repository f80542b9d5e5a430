// gvsd's main thread.
#include "gvs/daemon/app.hpp"

#include <pthread.h>
#include <signal.h>

#include <cerrno>
#include <cstring>
#include <optional>
#include <string>

#include <CLI/CLI.hpp>
#include <spdlog/spdlog.h>

#include "gvs/can/sink.hpp"
#include "gvs/drivers/clock.hpp"
#include "gvs/daemon/command_line.hpp"
#include "gvs/daemon/config.hpp"
#include "gvs/daemon/config_keys.hpp"
#include "gvs/daemon/frame_estimator.hpp"
#include "gvs/daemon/source_factory.hpp"
#include "gvs/daemon/health.hpp"
#include "gvs/daemon/logging.hpp"
#include "gvs/daemon/pipeline.hpp"
#include "gvs/daemon/rt.hpp"
#include "gvs/daemon/service_manager.hpp"
#include "gvs/daemon/startup_check.hpp"
#include "gvs/version.hpp"

namespace gvs::daemon {

namespace {

struct CommandLine {
  std::string config_file;
  std::string source_uri;
  std::string can_uri;
  std::optional<double> run_for_s;
  bool check_only = false;
  bool print_example = false;
  bool print_reference = false;
};

DaemonConfig load(const CommandLine& cli) {
  DaemonConfig c = cli.config_file.empty() ? DaemonConfig{} : load_config_file(cli.config_file);
  if (!cli.source_uri.empty()) c.source_uri = cli.source_uri;
  if (!cli.can_uri.empty()) c.can_uri = cli.can_uri;
  if (cli.run_for_s) c.run_for_s = *cli.run_for_s;
  return c;
}

/// Logs the real-time set-up once: one line when all is well, one warning
/// naming what was refused otherwise.
void report_realtime(const Pipeline& pipeline, const DaemonConfig& c, int mlock_errno) {
  const ThreadConfig* wanted[] = {&c.capture_thread, &c.processing_thread, &c.sender_thread};
  std::string threads;
  for (std::size_t i = 0; i < kThreadCount; ++i) {
    threads += fmt::format("{}{}: {}", i == 0 ? "" : "; ", role_name(static_cast<ThreadRole>(i)),
                           describe(pipeline.rt_reports()[i], *wanted[i]));
  }
  const bool rt_ok = pipeline.realtime() && mlock_errno == 0;
  const std::string memory = !c.lock_memory ? "memory not locked (configured)"
                             : mlock_errno == 0 ? (c.lock_on_fault ? "memory locked as touched (MCL_ONFAULT)"
                                                                   : "memory locked whole")
                                                : fmt::format("mlockall refused: {}", std::strerror(mlock_errno));
  if (rt_ok) {
    spdlog::info("real-time: {}; {}; stacks of {} KiB, {} KiB prefaulted", threads, memory, c.stack_kb,
                 c.prefault_stack_kb);
  } else {
    spdlog::warn(
        "real-time set-up incomplete, running anyway: {}; {}. For real-time operation run as root or grant "
        "CAP_SYS_NICE and CAP_IPC_LOCK (systemd: AmbientCapabilities=CAP_SYS_NICE CAP_IPC_LOCK, "
        "LimitRTPRIO=99, LimitMEMLOCK=infinity)",
        threads, memory);
  }
}

void log_sink_events(Pipeline& pipeline) {
  can::SinkEvent e;
  while (pipeline.pop_sink_event(e)) {
    const auto level = e.kind == can::SinkEventKind::InterfaceUp || e.kind == can::SinkEventKind::ErrorActive ||
                               e.kind == can::SinkEventKind::Restarted
                           ? spdlog::level::info
                           : spdlog::level::warn;
    spdlog::log(level, "CAN {}: {} (detail {})", pipeline.sink_description(), can::to_string(e.kind), e.detail);
  }
}

/// SIGHUP: re-read the file, apply what can change while running.
void reload(const CommandLine& cli, DaemonConfig& running, Pipeline& pipeline) {
  notify_service_manager(fmt::format("RELOADING=1\nMONOTONIC_USEC={}", drivers::mono_now_ns() / 1000));
  if (cli.config_file.empty()) {
    spdlog::info("SIGHUP: no --config file, nothing to reload");
  } else {
    try {
      DaemonConfig fresh = load(cli);
      for (const std::string& key : restart_only_changes(running, fresh)) {
        spdlog::warn("SIGHUP: {} changed in {}; it takes effect at the next restart", key, cli.config_file);
      }
      for (const std::string& change : apply_reloadable_keys(running, fresh)) {
        spdlog::info("SIGHUP: applying {}", change);
      }
      pipeline.apply_reloadable(running);
      spdlog::set_level(spdlog::level::from_str(running.log_level));
      spdlog::info("SIGHUP: reloaded {} (staleness limit {} ms, min quality {}, max acceleration {} m/s^2, "
                   "exposure {} max {} us, log level {}, health every {} s)",
                   cli.config_file, running.staleness_limit_ms, running.min_quality,
                   running.plausibility.max_accel_mps2, running.exposure_mode, running.exposure_max_us,
                   running.log_level, running.health_interval_s);
    } catch (const std::exception& e) {
      spdlog::error("SIGHUP: keeping the running configuration: {}", e.what());
    }
  }
  notify_service_manager("READY=1");
}

int run(const CommandLine& cli) {
  const bool journal = running_under_systemd();
  setup_logging("info", journal);
  DaemonConfig config;
  try {
    config = load(cli);
  } catch (const ConfigError& e) {
    spdlog::critical("configuration: {}", e.what());
    return 1;
  }
  if (cli.check_only) {
    try {
      (void)check_startup(config);
    } catch (const std::exception& e) {
      spdlog::critical("start-up: {}", describe_exception(e));
      return 1;
    }
    // stdout, not the log: `gvsd --check-config` is run by hand or by a
    // package script before a reload or restart.
    fmt::print("{}: configuration OK (source {}, CAN {}, estimator {}, exposure {})\n", config.origin,
               config.source_uri, config.can_uri, config.estimator_method, config.exposure_mode);
    return 0;
  }
  spdlog::set_level(spdlog::level::from_str(config.log_level));
  if (const int e = set_thread_memory_defaults(config.stack_kb); e != 0) {
    spdlog::warn("threads keep the default stack size ({} KiB refused: {})", config.stack_kb, std::strerror(e));
  }

  sigset_t signals;
  sigemptyset(&signals);
  sigaddset(&signals, SIGTERM);
  sigaddset(&signals, SIGINT);
  sigaddset(&signals, SIGHUP);
  // The stop/reload signals are blocked before any thread exists, so every
  // thread inherits the mask (the RT threads, a replay's decoder, the
  // camera library's threads) and the main thread takes them with
  // sigtimedwait: no handler runs on another thread, and a signal that
  // comes while the main thread is busy never falls to a thread that would
  // end the process without the Stopping message. One that comes during
  // start-up waits for the main loop.
  pthread_sigmask(SIG_BLOCK, &signals, nullptr);

  std::unique_ptr<Pipeline> pipeline;
  int mlock_errno = 0;
  try {
    auto source = make_frame_source(config);
    auto estimator = make_frame_estimator(config.estimator_method, source->geometry(), config.height);
    can::SinkOptions sink_options;
    auto sink = can::open_sink(config.can_uri, sink_options);
    spdlog::info("gvsd: source {}, estimator {}, CAN {} (base ID 0x{:03X}, every {} ms, status every {} ms), "
                 "stale after {} ms, min quality {}, max acceleration {} m/s^2, config {}",
                 source->describe(), estimator->name(), sink->description(), config.base_id, config.period_ms,
                 config.status_period_ms, config.staleness_limit_ms, config.min_quality,
                 config.plausibility.max_accel_mps2, config.origin);
    if (config.lock_memory) mlock_errno = lock_all_memory(config.lock_on_fault);
    PipelineHooks hooks;
    if (config.run_for_s > 0.0) {
      hooks.max_ticks = static_cast<std::uint64_t>(config.run_for_s * 1000.0 / config.period_ms + 0.5);
    }
    pipeline = std::make_unique<Pipeline>(config, std::move(source), std::move(estimator), std::move(sink), hooks);
    if (config.light.driver != "none") spdlog::info("gvsd: light and trigger: {}", pipeline->light_description());
    if (config.align_to_frames) {
      const auto q = SlotPhaseLock::modulus_ns(config.period_ms * drivers::kNsPerMs, pipeline->source().nominal_fps());
      spdlog::info("gvsd: CAN slots aligned to the frames: each slot 1 ms after the second slowest of the last 64 "
                   "estimates would be published, modulo {:.2f} ms (the period stays {} ms, each within 0.1 ms)",
                   static_cast<double>(q.value_or(0)) / 1e6, config.period_ms);
    }
    if (config.height.source == "can") {
      spdlog::info("gvsd: speed scale: height from CAN ID 0x{:X} on {} over a nominal {} mm (GVS_ScaleSource external "
                   "while its frames arrive)",
                   config.height.can_id, config.height.interface.empty() ? config.can_uri : config.height.interface,
                   config.height.nominal_mm);
    } else if (config.height.source == "lasers") {
      spdlog::info("gvsd: speed scale: height, pitch and roll from the laser dots of {} over a nominal {} mm "
                   "(GVS_ScaleSource laser_dots in frames where every dot is found)",
                   config.height.lasers_file, config.height.nominal_mm);
    } else {
      spdlog::info("gvsd: speed scale: nominal, uncorrected for heave, pitch and roll (no [height] source; "
                   "GVS_FaultScaleUncorrected is set)");
    }
    pipeline->start();
  } catch (const std::exception& e) {
    spdlog::critical("start-up: {}", describe_exception(e));
    return 1;
  }
  report_realtime(*pipeline, config, config.lock_memory ? mlock_errno : 0);

  const std::uint64_t watchdog_usec = service_watchdog_usec();
  const bool watchdog = watchdog_usec > 0;
  const std::int64_t watchdog_every_ns = watchdog ? static_cast<std::int64_t>(watchdog_usec) * 1000 / 2 : 0;
  notify_service_manager("READY=1\nSTATUS=starting");
  if (watchdog) spdlog::info("systemd watchdog every {} ms (fed while every thread makes progress)", watchdog_usec / 1000);

  const std::int64_t started_ns = drivers::mono_now_ns();
  std::int64_t next_health_ns = started_ns + static_cast<std::int64_t>(config.health_interval_s * 1e9);
  std::int64_t next_watchdog_ns = started_ns;
  WatchdogGate watchdog_gate(pipeline->progress());
  HealthSnapshot last_health = snapshot(pipeline->counters());
  std::int64_t last_health_ns = started_ns;
  std::string stop_reason;

  while (stop_reason.empty()) {
    const timespec wait = drivers::to_timespec(20 * drivers::kNsPerMs);
    siginfo_t info{};
    const int sig = sigtimedwait(&signals, &info, &wait);
    const std::int64_t now = drivers::mono_now_ns();
    if (sig == SIGTERM || sig == SIGINT) {
      stop_reason = sig == SIGTERM ? "SIGTERM" : "SIGINT";
      break;
    }
    if (sig == SIGHUP) reload(cli, config, *pipeline);
    if (pipeline->run_complete()) stop_reason = fmt::format("--run-for {} s done", config.run_for_s);
    if (pipeline->source_ended()) stop_reason = "end of the source";

    log_sink_events(*pipeline);
    for (const std::string& line : pipeline->take_source_log_lines()) spdlog::warn("{}", line);
    if (watchdog && now >= next_watchdog_ns) {
      if (watchdog_gate.should_feed(pipeline->progress())) notify_service_manager("WATCHDOG=1");
      next_watchdog_ns = now + watchdog_every_ns;
    }
    if (now >= next_health_ns) {
      const HealthSnapshot h = snapshot(pipeline->counters());
      const PublishedEstimate latest = pipeline->latest();
      const std::string camera = pipeline->source().health_text();
      spdlog::info("{}{}{}", format_health_line(h, last_health, latest, now,
                                                static_cast<double>(now - last_health_ns) / 1e9),
                   camera.empty() ? "" : " | ", camera);
      notify_service_manager("STATUS=" + format_status_text(h, latest, now));
      last_health = h;
      last_health_ns = now;
      next_health_ns = now + static_cast<std::int64_t>(config.health_interval_s * 1e9);
    }
  }

  notify_service_manager("STOPPING=1");
  const std::int64_t stop_ns = drivers::mono_now_ns();
  pipeline->request_stop();
  pipeline->join();
  log_sink_events(*pipeline);
  for (const std::string& line : pipeline->take_source_log_lines()) spdlog::warn("{}", line);
  const HealthSnapshot h = snapshot(pipeline->counters());
  spdlog::info("{}", format_health_line(h, last_health, pipeline->latest(), drivers::mono_now_ns(),
                                        static_cast<double>(drivers::mono_now_ns() - last_health_ns) / 1e9));
  spdlog::info("stopped ({}) in {:.1f} ms after {:.1f} s", stop_reason,
               static_cast<double>(drivers::mono_now_ns() - stop_ns) / 1e6,
               static_cast<double>(stop_ns - started_ns) / 1e9);
  return 0;
}

}  // namespace

int gvsd_main(int argc, char** argv) {
  CLI::App app{
      "gvsd: ground velocity sensor daemon. Frames from a camera (or the simulator, or a recorded dataset) "
      "in, velocity on the CAN bus every 20 ms out.",
      "gvsd"};
  app.set_version_flag("--version", std::string("gvsd ") + GVS_VERSION + " (" + GVS_GIT_COMMIT + ")",
                       "print the version and the git commit, then exit");
  app.footer(
      "Signals: SIGTERM or SIGINT stop gvsd; SIGHUP reloads the configuration's reloadable keys.\n"
      "Exit status: 0 stopped (a signal, --run-for, the end of a replay); 1 configuration or start-up refused (the "
      "log says why); 2 bad command line.\n"
      "Files: /etc/gvsd/gvsd.toml, the configuration the Debian package's gvsd.service runs with.\n"
      "Documentation: docs/daemon.md (configuration, threads), docs/deployment.md (the service on the car); in the "
      "Debian package under /usr/share/doc/gvs/; man gvs.");
  CommandLine cli;
  app.add_option("--config", cli.config_file, "TOML configuration file (see systemd/gvsd.toml)")
      ->check(CLI::ExistingFile);
  app.add_option("--source", cli.source_uri, "frame source: sim:SCENARIO | replay:DIR | libcamera[:ID] (default sim:sine)");
  app.add_option("--can", cli.can_uri, "CAN output: socketcan:IFACE | candump:PATH ('-' = stdout) (default candump:-)");
  app.add_option("--run-for", cli.run_for_s, "stop after this many seconds (exactly that many CAN periods)")
      ->check(positive_number());
  app.add_flag("--check-config", cli.check_only,
               "check the configuration as start-up does (every key, type and range; source, estimator, CAN "
               "URI) without opening a device, print a summary and exit: 0 = OK, 1 = refused, saying why");
  app.add_flag("--print-example-config", cli.print_example,
               "print the example configuration (systemd/gvsd.toml: every key at its default) and exit");
  app.add_flag("--print-config-reference", cli.print_reference,
               "print the configuration reference in Markdown (docs/daemon.md) and exit");
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // Usage errors exit 2, as getopt tools do; --help and --version exit 0.
    return app.exit(e) == 0 ? 0 : 2;
  }
  if (cli.print_example) {
    fmt::print("{}", example_config_text());
    return 0;
  }
  if (cli.print_reference) {
    fmt::print("{}", config_reference_markdown());
    return 0;
  }
  return run(cli);
}

}  // namespace gvs::daemon
