// libFuzzer target: gvsd's configuration parser (the TOML of /etc/gvsd/gvsd.toml).
// Any text must either parse or be refused with a ConfigError naming the key;
// any other exception, a crash or a sanitizer report is a finding.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "gvs/daemon/config.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  try {
    const gvs::daemon::DaemonConfig c = gvs::daemon::parse_config(text, "fuzz.toml");
    // A configuration that parses must be inside the documented ranges.
    if (c.period_ms < 1 || c.ring_slots < 2) __builtin_trap();
  } catch (const gvs::daemon::ConfigError&) {
  }
  return 0;
}
