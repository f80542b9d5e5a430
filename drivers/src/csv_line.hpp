// Splitting one line of the dataset's CSV files. The files are plain
// comma-separated values without quoting (no field contains a comma).
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace gvs::drivers::detail {

/// Splits `line` at commas; a trailing '\r' is dropped.
std::vector<std::string_view> split_csv(std::string_view line);

/// Parses a whole field as a number; false when it is not one (or empty).
bool parse_int(std::string_view field, std::int64_t& out);
bool parse_double(std::string_view field, double& out);

/// Column positions by header name; -1 when absent.
struct Columns {
  std::vector<std::string> names;
  [[nodiscard]] int find(std::string_view name) const;
};
Columns parse_header(std::string_view line);

}  // namespace gvs::drivers::detail
