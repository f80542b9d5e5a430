// Writing calibrated values into a gvsd configuration file (gvs calibrate),
// keeping everything else of the file as it was: comments, order, other keys.
#pragma once

#include <filesystem>
#include <string>
#include <utility>
#include <vector>

namespace gvs::daemon {

/// Sets `key = value` in `[section]` of the TOML text: replaces the value of
/// an existing key (its trailing comment stays), adds the key at the end of
/// the section, or appends the section. Only plain `key = value` lines of
/// top-level tables are touched; the result is checked with parse_config,
/// which throws ConfigError naming the key when a value is out of range.
std::string set_config_numbers(const std::string& toml_text, const std::string& section,
                               const std::vector<std::pair<std::string, double>>& values,
                               const std::string& origin);

/// The same on a file, written atomically (temporary file, then rename).
/// A missing file is created. Throws ConfigError (bad value, unreadable or
/// unwritable file, with the path).
void set_config_numbers_in_file(const std::filesystem::path& file, const std::string& section,
                                const std::vector<std::pair<std::string, double>>& values);

}  // namespace gvs::daemon
