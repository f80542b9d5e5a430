#include "gvs/daemon/command_line.hpp"

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "gvs/dsp/estimator.hpp"
#include "gvs/version.hpp"

namespace gvs::daemon {

namespace {

/// Strict decimal parse: the whole text, finite. Returns false otherwise.
bool parse_number(const std::string& text, double& value) {
  if (text.empty()) return false;
  errno = 0;
  char* end = nullptr;
  value = std::strtod(text.c_str(), &end);
  return end != nullptr && *end == '\0' && errno == 0 && std::isfinite(value);
}

std::string shortest(double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%g", v);
  return buf;
}

std::string not_a_number(const std::string& text) { return "'" + text + "' is not a number"; }

std::string subcommand_list(const CLI::App& app) {
  std::string names;
  for (const CLI::App* sub : app.get_subcommands([](const CLI::App*) { return true; })) {
    names += (names.empty() ? "" : ", ") + sub->get_name();
  }
  return names;
}

}  // namespace

CLI::Validator number_in(double lo, double hi) {
  return CLI::Validator(
      [lo, hi](std::string& text) -> std::string {
        double v = 0.0;
        if (!parse_number(text, v)) return not_a_number(text);
        if (v < lo || v > hi) return text + " is outside " + shortest(lo) + " .. " + shortest(hi);
        return {};
      },
      "NUMBER in " + shortest(lo) + " .. " + shortest(hi));
}

CLI::Validator whole_number_in(long lo, long hi) {
  return CLI::Validator(
      [lo, hi](std::string& text) -> std::string {
        double v = 0.0;
        if (!parse_number(text, v)) return not_a_number(text);
        if (v != std::floor(v)) return "'" + text + "' is not a whole number";
        if (v < static_cast<double>(lo) || v > static_cast<double>(hi)) {
          return text + " is outside " + std::to_string(lo) + " .. " + std::to_string(hi);
        }
        return {};
      },
      "WHOLE NUMBER in " + std::to_string(lo) + " .. " + std::to_string(hi));
}

CLI::Validator positive_number() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        double v = 0.0;
        if (!parse_number(text, v)) return not_a_number(text);
        if (!(v > 0.0)) return text + " is not above 0; give a positive number";
        return {};
      },
      "NUMBER > 0");
}

CLI::Validator seed_number() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        const bool digits = !text.empty() && text.find_first_not_of("0123456789") == std::string::npos;
        errno = 0;
        if (digits) (void)std::strtoull(text.c_str(), nullptr, 10);
        if (!digits || errno == ERANGE) {
          return "'" + text + "' is not a seed; give a whole number 0 .. 18446744073709551615";
        }
        return {};
      },
      "SEED 0 .. 2^64-1");
}

std::string method_list() {
  std::string names;
  for (const std::string& n : dsp::estimator_names()) names += (names.empty() ? "" : ", ") + n;
  return names + " (gvs: this project's estimator; thesis*: the 2022 thesis's methods, kept as baselines)";
}

CLI::Validator method_check() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        for (const std::string& n : dsp::estimator_names()) {
          if (text == n) return {};
        }
        std::string names;
        for (const std::string& n : dsp::estimator_names()) names += (names.empty() ? "" : ", ") + n;
        return "unknown method '" + text + "'; choose one of: " + names;
      },
      "METHOD");
}

int usage_exit(const CLI::App& app, const CLI::ParseError& e) {
  const int rc = app.exit(e);
  return rc == 0 ? 0 : kUsageExitCode;
}

bool check_subcommands(const CLI::App& app, int argc, const char* const* argv) {
  const CLI::App* current = &app;
  std::string path = app.get_name();
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (current->get_subcommands([](const CLI::App*) { return true; }).empty()) return true;
    if (arg == "--help" || arg == "-h" || arg == "--version") return true;
    if (arg.rfind('-', 0) == 0) break;  // an option where the subcommand belongs
    const CLI::App* sub = nullptr;
    try {
      sub = current->get_subcommand(arg);
    } catch (const CLI::OptionNotFound&) {
      std::fprintf(stderr, "%s: unknown command '%s'; the commands are: %s (%s --help)\n", path.c_str(),
                   arg.c_str(), subcommand_list(*current).c_str(), path.c_str());
      return false;
    }
    current = sub;
    path += " " + sub->get_name();
  }
  if (current->get_subcommands([](const CLI::App*) { return true; }).empty() ||
      current->get_require_subcommand_min() == 0) {
    return true;
  }
  std::fprintf(stderr, "%s: give a command: %s (%s --help)\n", path.c_str(), subcommand_list(*current).c_str(),
               path.c_str());
  return false;
}

std::string version_text(const std::string& program) {
  return program + " " + GVS_VERSION + " (" + GVS_GIT_COMMIT + ")";
}

}  // namespace gvs::daemon
