// The subcommands of the `gvs` tool; each file cmd_<name>.cpp registers one.
#pragma once

namespace CLI {
class App;
}

namespace gvs::cli {

/// Thrown by a command stopped by SIGINT / SIGTERM after cleaning up; gvs
/// exits with 130, the shell's code for an interrupted command.
struct Interrupted {};

void register_sim(CLI::App& app);
void register_replay(CLI::App& app);
void register_eval(CLI::App& app);
void register_monitor(CLI::App& app);
void register_calibrate(CLI::App& app);
void register_snapshot(CLI::App& app);
void register_record(CLI::App& app);

}  // namespace gvs::cli
