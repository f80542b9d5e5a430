// gvsd's configuration keys, each declared once in one table
// (daemon/src/gvsd/config_keys.cpp): section, name, where the value lives,
// range or allowed values, unit, whether SIGHUP applies it, one line of help.
// Parsing, range checks, SIGHUP reload, the example file systemd/gvsd.toml
// and the reference in docs/daemon.md are all made from it.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

namespace gvs::daemon {

struct DaemonConfig;

/// Where a key's value lives in a DaemonConfig; the alternative is the type.
/// The default is that field's initializer (DaemonConfig{}), written nowhere else.
using ConfigField = std::variant<double*, int*, std::int64_t*, std::uint32_t*, bool*, std::string*>;

enum class Reload : std::uint8_t {
  restart,  ///< read at start-up only; a change on SIGHUP is logged as "takes effect at the next restart"
  sighup,   ///< applied by SIGHUP while running
};

/// One [section] of the file ("threads.capture" is the table [threads.capture]).
struct ConfigSection {
  std::string_view name;
  std::string_view help;  ///< a paragraph; '\n' separates lines of the example's comment
};

struct ConfigKey {
  std::string_view section;
  std::string_view name;
  ConfigField (*field)(DaemonConfig&) = nullptr;
  double min = 0.0;  ///< numbers: inclusive range
  double max = 0.0;
  std::string_view unit;  ///< "ms", "m/s^2", "" when none
  /// Text keys with a closed set of values; nullptr = any non-empty text.
  std::vector<std::string> (*allowed)() = nullptr;
  Reload reload = Reload::restart;
  std::string_view help;  ///< one line
  /// Read only in this case (e.g. `driver = "gpio"`): the example shows the
  /// key commented out.
  std::string_view only_when;
  /// Shown in the example instead of the default when the default means
  /// "not set" and lies outside the range (e.g. [light] led_line = -1).
  std::string_view example;
  std::string_view note;  ///< meaning of special values, added to the range ("-1 = any CPU")
  bool hex = false;       ///< integers shown as 0x...
};

/// A check across keys, run after every key was read.
struct ConfigRule {
  std::string_view section;
  std::string_view text;                     ///< for the reference: what must hold
  void (*check)(const DaemonConfig&) = nullptr;  ///< throws ConfigError naming the file and keys
};

std::span<const ConfigSection> config_sections();
std::span<const ConfigKey> config_keys();
std::span<const ConfigRule> config_rules();

/// "section.name" (e.g. "can.staleness_limit_ms").
std::string key_path(const ConfigKey& key);
/// The value as TOML text: "20", "0.3", "\"sim:sine\"", "true", "0x300".
std::string toml_value(const ConfigKey& key, const DaemonConfig& config);
/// "1 .. 1000 ms", "one of: fixed, adaptive, double-pulse", "true or false", "text".
std::string allowed_text(const ConfigKey& key);
/// Whether the key holds the same value in both.
bool same_value(const ConfigKey& key, const DaemonConfig& a, const DaemonConfig& b);
/// Sets `to`'s value of the key to `from`'s.
void copy_value(const ConfigKey& key, const DaemonConfig& from, DaemonConfig& to);

/// The documented example file (systemd/gvsd.toml), every key at its default.
std::string example_config_text();
/// The configuration reference in Markdown (docs/daemon.md, "Configuration reference").
std::string config_reference_markdown();

}  // namespace gvs::daemon
