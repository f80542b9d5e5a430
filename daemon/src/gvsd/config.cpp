// Reads gvsd's TOML configuration with strict checking against the table of
// keys (config_keys.cpp): every key must be known, of the right type and
// inside its range, or start-up stops with a message naming the key and what
// is allowed.
#include "gvs/daemon/config.hpp"

#include <algorithm>
#include <cerrno>
#include <filesystem>
#include <fstream>
#include <optional>
#include <set>
#include <sstream>
#include <stdexcept>
#include <type_traits>
#include <variant>

#include <toml++/toml.h>

#include "gvs/daemon/config_keys.hpp"

namespace gvs::daemon {

namespace {

std::string where(const std::string& origin, const toml::node& node) {
  std::ostringstream s;
  s << origin;
  if (node.source().begin.line > 0) s << ':' << node.source().begin.line;
  return s.str();
}

std::string fmt_num(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

[[noreturn]] void fail(const std::string& origin, const toml::node& n, std::string_view section,
                       std::string_view key, const std::string& what, const std::string& allowed) {
  std::string msg = where(origin, n) + ": [" + std::string(section) + "] " + std::string(key) + " " + what;
  if (!allowed.empty()) msg += " (" + allowed + ")";
  throw ConfigError(msg);
}

/// What a refusal says is allowed: "allowed 1 .. 1000 ms", "allowed integers
/// -1 .. 1023; -1 = any CPU", "one of: fixed, adaptive, double-pulse".
std::string allowed_message(const ConfigKey& key, bool integer) {
  const std::string text = allowed_text(key);
  if (key.allowed != nullptr) return text;
  std::string out = integer ? "allowed integers " : "allowed ";
  out += text;
  if (!key.note.empty()) out.append("; ").append(key.note);
  return out;
}

/// Reads one key's TOML value into its field, checking type and range.
void read_key(const ConfigKey& key, const toml::node& n, DaemonConfig& c) {
  const std::string& origin = c.origin;
  std::visit(
      [&](auto* out) {
        using T = std::remove_pointer_t<decltype(out)>;
        if constexpr (std::is_same_v<T, double>) {
          double v = 0.0;
          if (const auto* i = n.as_integer()) {
            v = static_cast<double>(i->get());
          } else if (const auto* f = n.as_floating_point()) {
            v = f->get();
          } else {
            fail(origin, n, key.section, key.name, "must be a number", allowed_message(key, false));
          }
          if (!(v >= key.min && v <= key.max)) {
            fail(origin, n, key.section, key.name, "= " + fmt_num(v) + " is out of range", allowed_message(key, false));
          }
          *out = v;
        } else if constexpr (std::is_same_v<T, bool>) {
          const auto* b = n.as_boolean();
          if (b == nullptr) fail(origin, n, key.section, key.name, "must be true or false", "");
          *out = b->get();
        } else if constexpr (std::is_same_v<T, std::string>) {
          const auto* s = n.as_string();
          if (s == nullptr) {
            fail(origin, n, key.section, key.name, "must be a string",
                 key.allowed != nullptr ? allowed_text(key) : "");
          }
          const std::string& v = s->get();
          if (v.empty()) fail(origin, n, key.section, key.name, "must not be empty", "");
          if (key.allowed != nullptr) {
            const std::vector<std::string> allowed = key.allowed();
            if (std::find(allowed.begin(), allowed.end(), v) == allowed.end()) {
              fail(origin, n, key.section, key.name, "= \"" + v + "\" is not allowed", allowed_text(key));
            }
          }
          *out = v;
        } else {
          const auto* i = n.as_integer();
          if (i == nullptr) fail(origin, n, key.section, key.name, "must be an integer", allowed_message(key, true));
          const std::int64_t v = i->get();
          // Compared as integers: above 2^53 a double cannot tell neighbours apart.
          if (v < static_cast<std::int64_t>(key.min) || v > static_cast<std::int64_t>(key.max)) {
            fail(origin, n, key.section, key.name, "= " + std::to_string(v) + " is out of range",
                 allowed_message(key, true));
          }
          *out = static_cast<T>(v);
        }
      },
      key.field(c));
}

/// The table of [a.b]; nullptr when the file has none. A non-table value
/// under that name is refused naming it.
const toml::table* find_table(const toml::table& root, std::string_view section, const std::string& origin) {
  const toml::table* t = &root;
  std::string parent = "top level";
  std::string_view rest = section;
  while (t != nullptr && !rest.empty()) {
    const auto dot = rest.find('.');
    const std::string_view part = rest.substr(0, dot);
    const toml::node* n = t->get(part);
    if (n == nullptr) return nullptr;
    t = n->as_table();
    if (t == nullptr) fail(origin, *n, parent, part, "must be a table", "");
    parent = std::string(section.substr(0, section.size() - rest.size() + part.size()));
    rest = dot == std::string_view::npos ? std::string_view() : rest.substr(dot + 1);
  }
  return t;
}

/// Names that may appear in [section]: its keys and its sub-tables.
std::set<std::string> names_in(std::string_view section) {
  std::set<std::string> names;
  for (const ConfigKey& k : config_keys()) {
    if (k.section == section) names.emplace(k.name);
  }
  const std::string prefix = section.empty() ? std::string() : std::string(section) + ".";
  for (const ConfigSection& s : config_sections()) {
    if (s.name.size() <= prefix.size() || s.name.substr(0, prefix.size()) != prefix) continue;
    const std::string_view child = s.name.substr(prefix.size());
    names.emplace(child.substr(0, child.find('.')));
  }
  return names;
}

void refuse_unknown(const toml::table& table, std::string_view section, const std::string& origin) {
  const std::set<std::string> known = names_in(section);
  for (auto&& [k, v] : table) {
    if (known.count(std::string(k.str())) != 0) continue;
    std::string keys;
    for (const auto& kk : known) keys.append(keys.empty() ? "" : ", ").append(kk);
    throw ConfigError(where(origin, v) + ": unknown key '" + std::string(k.str()) + "' in [" +
                      std::string(section.empty() ? "top level" : section) + "]; known keys: " + keys);
  }
}

// toml++ 3.3.0 (Debian 12) reaches __builtin_unreachable() -- undefined
// behaviour, found by fuzz_config -- when it tests some non-ASCII characters
// as whitespace: outside strings and comments, and after a line-ending
// backslash in a multi-line """ string. So gvsd first parses a stand-in of
// the file with every non-ASCII byte replaced by '~', which is never valid
// outside a string or comment: if that parses, every non-ASCII character is
// in a string or a comment. Same lines, same structure; only text differs.
constexpr char kNonAsciiStandIn = '~';

std::string ascii_stand_in(std::string_view text) {
  std::string s(text);
  for (char& c : s)
    if (static_cast<unsigned char>(c) >= 0x80) c = kNonAsciiStandIn;
  return s;
}

// In a file that is valid TOML: the 1-based line of the first non-ASCII
// byte inside a multi-line basic string ("""), if any. The scan follows
// TOML's string and comment syntax, exact for valid TOML.
std::optional<int> line_of_non_ascii_in_multi_line_basic_string(std::string_view s) {
  enum class In { code, comment, basic, literal, multi_basic, multi_literal };
  In in = In::code;
  int line = 1;
  std::size_t i = 0;
  const auto starts = [&](std::string_view t) { return s.substr(i, t.size()) == t; };
  const auto skip_quotes = [&](char q) {  // a multi-line string may end in up to 5 quotes
    while (i + 1 < s.size() && s[i + 1] == q) ++i;
  };
  const auto escaped_quote_or_backslash = [&] {
    return s[i] == '\\' && i + 1 < s.size() && (s[i + 1] == '"' || s[i + 1] == '\\');
  };
  for (; i < s.size(); ++i) {
    const char c = s[i];
    if (c == '\n') ++line;
    switch (in) {
      case In::code:
        if (c == '#') {
          in = In::comment;
        } else if (starts("\"\"\"")) {
          i += 2;
          in = In::multi_basic;
        } else if (starts("'''")) {
          i += 2;
          in = In::multi_literal;
        } else if (c == '"') {
          in = In::basic;
        } else if (c == '\'') {
          in = In::literal;
        }
        break;
      case In::comment:
        if (c == '\n') in = In::code;
        break;
      case In::basic:
        if (escaped_quote_or_backslash()) {
          ++i;
        } else if (c == '"') {
          in = In::code;
        }
        break;
      case In::literal:
        if (c == '\'') in = In::code;
        break;
      case In::multi_basic:
        if (static_cast<unsigned char>(c) >= 0x80) return line;
        if (escaped_quote_or_backslash()) {
          ++i;
        } else if (starts("\"\"\"")) {
          skip_quotes('"');
          in = In::code;
        }
        break;
      case In::multi_literal:
        if (starts("'''")) {
          skip_quotes('\'');
          in = In::code;
        }
        break;
    }
  }
  return std::nullopt;
}

[[noreturn]] void refuse_invalid_toml(std::string_view text, const std::string& origin, const toml::parse_error& e) {
  const auto line = static_cast<std::size_t>(e.source().begin.line);
  std::ostringstream msg;
  msg << origin << ':' << line << ": not valid TOML: " << e.description();
  std::size_t begin = 0;  // the line's text, to say whether a non-ASCII character is the cause
  for (std::size_t n = 1; n < line && begin != std::string_view::npos; ++n) {
    begin = text.find('\n', begin);
    if (begin != std::string_view::npos) ++begin;
  }
  const std::string_view line_text =
      begin == std::string_view::npos ? std::string_view{} : text.substr(begin, text.find('\n', begin) - begin);
  if (std::any_of(line_text.begin(), line_text.end(), [](char c) { return static_cast<unsigned char>(c) >= 0x80; }))
    msg << " (a non-ASCII character, shown as '" << kNonAsciiStandIn
        << "', is allowed only in a quoted string or a comment)";
  throw ConfigError(msg.str());
}

toml::table parse_toml(std::string_view text, const std::string& origin) {
  if (text.substr(0, 3) == "\xEF\xBB\xBF") text.remove_prefix(3);  // UTF-8 byte-order mark
  try {
    (void)toml::parse(ascii_stand_in(text), origin);
  } catch (const toml::parse_error& e) {
    refuse_invalid_toml(text, origin, e);
  }
  if (const std::optional<int> line = line_of_non_ascii_in_multi_line_basic_string(text)) {
    throw ConfigError(origin + ':' + std::to_string(*line) +
                      ": a non-ASCII character in a multi-line \"\"\" string, which gvsd's TOML parser "
                      "(toml++ 3.3.0) cannot read safely; put the text in a one-line \"string\"");
  }
  try {
    return toml::parse(text, origin);
  } catch (const toml::parse_error& e) {
    refuse_invalid_toml(text, origin, e);
  }
}
}  // namespace

const std::vector<std::string>& log_level_names() {
  static const std::vector<std::string> names{"trace", "debug", "info", "warn", "error", "critical", "off"};
  return names;
}

DaemonConfig parse_config(std::string_view toml_text, const std::string& origin) {
  const toml::table root = parse_toml(toml_text, origin);

  DaemonConfig c;
  c.origin = origin;
  for (const ConfigSection& section : config_sections()) {
    const toml::table* table = find_table(root, section.name, origin);
    if (table == nullptr) continue;
    for (const ConfigKey& key : config_keys()) {
      if (key.section != section.name) continue;
      if (const toml::node* n = table->get(key.name)) read_key(key, *n, c);
    }
    refuse_unknown(*table, section.name, origin);
  }
  refuse_unknown(root, "", origin);
  for (const ConfigRule& rule : config_rules()) rule.check(c);
  return c;
}

DaemonConfig load_config_file(const std::filesystem::path& file) {
  std::ifstream in(file);
  if (!in) {
    // errno of the failed open: say which of the usual causes it is.
    const int why = errno;
    std::string cause = "does it exist?";
    if (why == EACCES) cause = "permission denied: the user gvsd runs as must be able to read it (the service: gvsd)";
    if (why == ENOENT) cause = "no such file";
    if (why == EISDIR || std::filesystem::is_directory(file)) cause = "it is a folder, not a file";
    throw ConfigError(file.string() + ": cannot read the configuration file (" + cause + ")");
  }
  std::ostringstream text;
  text << in.rdbuf();
  return parse_config(text.str(), file.string());
}

std::vector<std::string> restart_only_changes(const DaemonConfig& a, const DaemonConfig& b) {
  std::vector<std::string> changed;
  for (const ConfigKey& key : config_keys()) {
    if (key.reload == Reload::restart && !same_value(key, a, b)) changed.push_back(key_path(key));
  }
  return changed;
}

std::vector<std::string> apply_reloadable_keys(DaemonConfig& running, const DaemonConfig& reloaded) {
  std::vector<std::string> changed;
  for (const ConfigKey& key : config_keys()) {
    if (key.reload != Reload::sighup || same_value(key, running, reloaded)) continue;
    changed.push_back(key_path(key) + " = " + toml_value(key, reloaded) + " (was " + toml_value(key, running) + ")");
    copy_value(key, reloaded, running);
  }
  return changed;
}

}  // namespace gvs::daemon
