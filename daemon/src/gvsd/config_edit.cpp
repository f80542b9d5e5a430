#include "gvs/daemon/config_edit.hpp"

#include <fstream>
#include <sstream>

#include <fmt/format.h>

#include "gvs/daemon/config.hpp"

namespace gvs::daemon {

namespace {

std::string trim(const std::string& s) {
  const auto b = s.find_first_not_of(" \t\r");
  if (b == std::string::npos) return {};
  return s.substr(b, s.find_last_not_of(" \t\r") - b + 1);
}

/// "[name]" -> name; anything else (incl. "[[array]]") -> empty.
std::string table_name(const std::string& line) {
  const std::string t = trim(line.substr(0, line.find('#')));
  if (t.size() < 3 || t.front() != '[' || t.back() != ']' || t[1] == '[') return {};
  return trim(t.substr(1, t.size() - 2));
}

bool is_key_line(const std::string& line, const std::string& key) {
  const std::string t = trim(line);
  if (t.compare(0, key.size(), key) != 0) return false;
  const std::string rest = trim(t.substr(key.size()));
  return !rest.empty() && rest.front() == '=';
}

std::string replace_value(const std::string& line, const std::string& key, const std::string& value) {
  const auto hash = line.find('#');
  const std::string comment = hash == std::string::npos ? std::string() : line.substr(hash);
  const std::string indent = line.substr(0, line.find_first_not_of(" \t"));
  std::string out = indent + key + " = " + value;
  if (!comment.empty()) out += "  " + comment;
  return out;
}

}  // namespace

std::string set_config_numbers(const std::string& toml_text, const std::string& section,
                               const std::vector<std::pair<std::string, double>>& values,
                               const std::string& origin) {
  std::vector<std::string> lines;
  std::istringstream in(toml_text);
  for (std::string l; std::getline(in, l);) lines.push_back(l);

  for (const auto& [key, number] : values) {
    const std::string value = fmt::format("{}", number);
    std::ptrdiff_t header = -1;
    std::ptrdiff_t last_in_section = -1;
    std::ptrdiff_t found = -1;
    std::string current;
    for (std::size_t i = 0; i < lines.size(); ++i) {
      const std::string name = table_name(lines[i]);
      if (!name.empty() || trim(lines[i]).rfind("[[", 0) == 0) {
        current = name;
        if (name == section) header = static_cast<std::ptrdiff_t>(i);
        continue;
      }
      if (current != section) continue;
      if (!trim(lines[i]).empty() && trim(lines[i]).front() != '#') last_in_section = static_cast<std::ptrdiff_t>(i);
      if (is_key_line(lines[i], key)) found = static_cast<std::ptrdiff_t>(i);
    }
    const std::string line = key + " = " + value;
    if (found >= 0) {
      lines[static_cast<std::size_t>(found)] = replace_value(lines[static_cast<std::size_t>(found)], key, value);
    } else if (header >= 0) {
      const std::ptrdiff_t after = last_in_section >= 0 ? last_in_section : header;
      lines.insert(lines.begin() + after + 1, line);
    } else {
      if (!lines.empty() && !trim(lines.back()).empty()) lines.emplace_back();
      lines.push_back("[" + section + "]");
      lines.push_back(line);
    }
  }
  std::string out;
  for (const std::string& l : lines) out += l + "\n";
  (void)parse_config(out, origin);  // throws ConfigError naming the key
  return out;
}

void set_config_numbers_in_file(const std::filesystem::path& file, const std::string& section,
                                const std::vector<std::pair<std::string, double>>& values) {
  std::string text;
  if (std::filesystem::exists(file)) {
    std::ifstream in(file, std::ios::binary);
    if (!in) throw ConfigError(file.string() + ": cannot be read; check its permissions");
    std::ostringstream s;
    s << in.rdbuf();
    text = s.str();
  }
  const std::string out = set_config_numbers(text, section, values, file.string());
  const std::filesystem::path tmp = file.string() + ".tmp";
  {
    std::ofstream o(tmp, std::ios::binary | std::ios::trunc);
    o << out;
    if (!o) throw ConfigError(tmp.string() + ": cannot be written; check the folder's permissions");
  }
  std::error_code ec;
  std::filesystem::rename(tmp, file, ec);
  if (ec) throw ConfigError(file.string() + ": cannot be replaced (" + ec.message() + ")");
}

}  // namespace gvs::daemon
