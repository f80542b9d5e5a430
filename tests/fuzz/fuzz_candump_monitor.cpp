// libFuzzer target: what `gvs monitor` does with a candump -L log: every
// line through parse_candump_line, every frame through the decoder and
// statistics of MonitorState. Arbitrary bytes must never crash, read out of
// bounds or throw (both are noexcept on the monitor's live path).
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "gvs/can/candump.hpp"
#include "gvs/can/monitor.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  std::string_view rest(reinterpret_cast<const char*>(data), size);
  gvs::can::MonitorState monitor;
  std::uint64_t parsed = 0;
  while (!rest.empty()) {
    const std::size_t end = rest.find('\n');
    const std::string_view line = rest.substr(0, end);
    rest = end == std::string_view::npos ? std::string_view() : rest.substr(end + 1);
    if (const auto f = gvs::can::parse_candump_line(line)) {
      if (f->frame.len > 8) __builtin_trap();  // classical CAN only
      monitor.feed(f->frame, f->t_ns);
      ++parsed;
    } else {
      monitor.note_malformed_line();
    }
  }
  if (monitor.total_frames() != parsed) __builtin_trap();
  return 0;
}
