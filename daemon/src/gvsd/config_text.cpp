// The example file and the Markdown reference, both printed from the table of
// keys so that systemd/gvsd.toml and docs/daemon.md cannot drift from what
// gvsd reads (tests compare them with this output).
#include <algorithm>
#include <sstream>
#include <variant>

#include <fmt/format.h>

#include "gvs/daemon/config.hpp"
#include "gvs/daemon/config_keys.hpp"

namespace gvs::daemon {

namespace {

constexpr const char* kExampleHeader =
    "# gvsd configuration: the documented example (docs/daemon.md, \"Configuration reference\").\n"
    "# Printed by `gvsd --print-example-config` from the table of keys\n"
    "# (daemon/src/gvsd/config_keys.cpp); a test keeps this file equal to it.\n"
    "#\n"
    "# Every key is optional; the value shown is the built-in default. An unknown\n"
    "# key, a value of the wrong type or out of its range stops gvsd at start-up\n"
    "# with a message naming the key and the allowed range. The command line\n"
    "# (--source, --can, --run-for) overrides this file. SIGHUP re-reads the file\n"
    "# and applies the keys marked \"reloadable\"; a change of any other key is\n"
    "# logged as taking effect at the next restart. `gvsd --check-config` runs\n"
    "# every check of start-up that opens no device.\n";

std::vector<std::string> lines_of(std::string_view text) {
  std::vector<std::string> lines;
  std::istringstream in{std::string(text)};
  for (std::string l; std::getline(in, l);) lines.push_back(l);
  return lines;
}

bool is_text_or_bool(const ConfigKey& key) {
  DaemonConfig c;
  const ConfigField f = key.field(c);
  return (std::holds_alternative<std::string*>(f) && key.allowed == nullptr) || std::holds_alternative<bool*>(f);
}

std::string type_name(const ConfigKey& key) {
  DaemonConfig c;
  const ConfigField f = key.field(c);
  if (std::holds_alternative<double*>(f)) return "number";
  if (std::holds_alternative<bool*>(f)) return "boolean";
  if (std::holds_alternative<std::string*>(f)) return "text";
  return "integer";
}

/// The value shown for a key: the default, or the example when the default
/// means "not set".
std::string shown_value(const ConfigKey& key, const DaemonConfig& defaults) {
  return key.example.empty() ? toml_value(key, defaults) : std::string(key.example);
}

std::string example_comment(const ConfigKey& key) {
  std::string c = std::string(key.help);
  if (!is_text_or_bool(key)) c += "; " + allowed_text(key);
  if (!key.note.empty()) c.append("; ").append(key.note);
  if (!key.example.empty()) c += "; not set by default";
  if (key.reload == Reload::sighup) c += "; reloadable";
  return c;
}

std::string md_cell(std::string_view text) {
  std::string out;
  for (const char ch : text) {
    if (ch == '|') out += '\\';
    out += ch;
  }
  return out;
}

/// A section's help as Markdown: indented lines become list items.
std::string md_paragraphs(std::string_view help) {
  std::string out;
  bool in_list = false;
  for (const std::string& l : lines_of(help)) {
    const bool item = l.rfind("  ", 0) == 0;
    if (item) {
      if (!in_list && !out.empty()) out += "\n";
      std::string t = l.substr(l.find_first_not_of(' '));
      const auto gap = t.find("  ");
      if (gap != std::string::npos) t = fmt::format("`{}`: {}", t.substr(0, gap), t.substr(t.find_first_not_of(' ', gap)));
      out += "- " + t + "\n";
    } else {
      if (in_list) out += "\n";
      out += l + "\n";
    }
    in_list = item;
  }
  return out;
}

}  // namespace

std::string example_config_text() {
  const DaemonConfig defaults;
  std::ostringstream out;
  out << kExampleHeader;
  for (const ConfigSection& section : config_sections()) {
    out << "\n[" << section.name << "]\n";
    for (const std::string& l : lines_of(section.help)) out << "# " << l << "\n";
    for (const ConfigRule& rule : config_rules()) {
      if (rule.section == section.name) out << "# Also checked: " << rule.text << ".\n";
    }
    std::vector<std::pair<std::string, std::string>> rows;
    std::size_t width = 0;
    for (const ConfigKey& key : config_keys()) {
      if (key.section != section.name) continue;
      std::string line = fmt::format("{}{} = {}", key.only_when.empty() ? "" : "#", key.name, shown_value(key, defaults));
      std::string comment = example_comment(key);
      if (!key.only_when.empty()) comment.append("; with ").append(key.only_when);
      width = std::max(width, line.size());
      rows.emplace_back(std::move(line), std::move(comment));
    }
    for (const auto& [line, comment] : rows) {
      out << line << std::string(width + 2 - line.size(), ' ') << "# " << comment << "\n";
    }
  }
  return out.str();
}

std::string config_reference_markdown() {
  const DaemonConfig defaults;
  std::ostringstream out;
  out << "Printed by `gvsd --print-config-reference` from the table of keys "
         "(`daemon/src/gvsd/config_keys.cpp`), like `systemd/gvsd.toml` (`gvsd --print-example-config`); "
         "a test keeps both equal to it. SIGHUP: *reload* = a running gvsd applies the new value, "
         "*restart* = logged as taking effect at the next restart.\n";
  for (const ConfigSection& section : config_sections()) {
    out << "\n### `[" << section.name << "]`\n\n" << md_paragraphs(section.help) << "\n";
    out << "| key | type | default | allowed | SIGHUP | meaning |\n|---|---|---|---|---|---|\n";
    for (const ConfigKey& key : config_keys()) {
      if (key.section != section.name) continue;
      std::string meaning(key.help);
      if (!key.note.empty()) meaning.append("; ").append(key.note);
      if (!key.only_when.empty()) meaning.append(" (read with ").append(key.only_when).append(")");
      const std::string def = key.example.empty() ? fmt::format("`{}`", toml_value(key, defaults)) : "not set";
      out << "| `" << key.name << "` | " << type_name(key) << " | " << md_cell(def) << " | "
          << md_cell(allowed_text(key)) << " | " << (key.reload == Reload::sighup ? "reload" : "restart") << " | "
          << md_cell(meaning) << " |\n";
    }
    for (const ConfigRule& rule : config_rules()) {
      if (rule.section == section.name) out << "\nAlso checked: " << rule.text << ".\n";
    }
  }
  return out.str();
}

}  // namespace gvs::daemon
