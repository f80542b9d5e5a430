// Command-line conventions shared by gvsd and the gvs subcommands: number
// checks that say "not a number" before "out of range", exit code 2 for
// usage errors, unknown subcommands named with the list of known ones,
// --version.
#pragma once

#include <string>

namespace CLI {
class App;
class ParseError;
class Validator;
}  // namespace CLI

namespace gvs::daemon {

/// Exit code of a usage error (bad option, value or subcommand), as getopt
/// tools and the shell's builtins use; runtime failures exit 1.
constexpr int kUsageExitCode = 2;

/// A decimal number in [lo, hi] (the message names both bounds).
CLI::Validator number_in(double lo, double hi);
/// A whole number in [lo, hi].
CLI::Validator whole_number_in(long lo, long hi);
/// A number above 0 (durations, sizes): 0 and negatives are refused.
CLI::Validator positive_number();
/// A seed: a whole number 0 .. 2^64-1 (no sign: "-3" would wrap around).
CLI::Validator seed_number();

/// The estimator methods, "gvs (this project's), thesis, ..." for --help,
/// and the check that refuses any other name as a usage error.
std::string method_list();
CLI::Validator method_check();

/// Prints CLI11's message for `e` and returns the process exit code: 0 for
/// --help and --version, kUsageExitCode for every usage error.
int usage_exit(const CLI::App& app, const CLI::ParseError& e);

/// Before parsing: when argv names no subcommand of `app` (or of the
/// subcommand it names, recursively) where one is required, prints what is
/// wrong and the subcommands to choose from and returns false.
bool check_subcommands(const CLI::App& app, int argc, const char* const* argv);

/// "gvs 0.1.0 (git 1a2b3c4d5e6f)": the version and the commit the build
/// was configured from.
std::string version_text(const std::string& program);

}  // namespace gvs::daemon
