// gvs_can_examples: prints the example frames for the independent DBC check
// (--json: one JSON object a line with the frame and every signal's expected
// physical value) or as a candump -L log (--candump), or the worked example
// of docs/can-interface.md (--worked-example).
#include <cstdio>
#include <cstring>

#include "example_cases.hpp"
#include "gvs/can/candump.hpp"
#include "gvs/can/e2e.hpp"

using namespace gvs::can;

int main(int argc, char** argv) {
  const char* mode = argc > 1 ? argv[1] : "--json";
  const auto cases = test::example_cases();
  if (std::strcmp(mode, "--json") == 0) {
    for (const auto& c : cases) {
      std::printf("{\"message\": \"%s\", \"id\": %u, \"data\": \"", c.message.c_str(), c.frame.id);
      for (std::size_t i = 0; i < c.frame.len; ++i) std::printf("%02X", c.frame.data[i]);
      std::printf("\", \"expect\": {");
      const char* sep = "";
      for (const auto& [name, value] : c.expect) {
        std::printf("%s\"%s\": %.6f", sep, name.c_str(), value);
        sep = ", ";
      }
      std::printf("}}\n");
    }
    return 0;
  }
  if (std::strcmp(mode, "--candump") == 0) {
    std::int64_t t_ns = 1'699'999'999'123'456'000;
    for (const auto& c : cases) {
      char line[kCandumpLineMax + 1];
      if (format_candump_line(c.frame, t_ns, "vcan0", line, sizeof line) == 0) return 1;
      std::fputs(line, stdout);
      t_ns += 20'000'000;
    }
    return 0;
  }
  if (std::strcmp(mode, "--sequence") == 0) {
    // 2 s of traffic as gvsd sends it (candump -L), with one GVS_Velocity
    // frame lost (cycle 50) and one corrupted (cycle 70): for gvs monitor.
    Encoder enc({});
    std::int64_t t_ns = 1'699'999'999'000'000'000;
    for (int cycle = 0; cycle < 100; ++cycle, t_ns += 20'000'000) {
      VelocityMsg v{true, true, true, true, 20.0 + 0.01 * cycle, 1.5, -3.0, 90.0};
      CanFrame frames[4];
      int n = 0;
      frames[n++] = enc.velocity(v);
      frames[n++] = enc.velocity_xy({true, 19.99, 0.52, 6});
      if (cycle % 5 == 0) {
        frames[n++] = enc.status({SensorState::Running, 0, 3, 0, 0, 33});  // GVS_Method 33: pair
        frames[n++] = enc.timing({800, 1900, 0});
      }
      if (cycle == 70) frames[0].data[4] ^= 0x01;
      for (int i = 0; i < n; ++i) {
        if (cycle == 50 && i == 0) continue;
        char line[kCandumpLineMax + 1];
        format_candump_line(frames[i], t_ns + i * 100'000, "vcan0", line, sizeof line);
        std::fputs(line, stdout);
      }
    }
    std::puts("this line is not candump");
    return 0;
  }
  if (std::strcmp(mode, "--worked-example") == 0) {
    const auto& c = cases.front();
    char line[kCandumpLineMax + 1];
    format_candump_line(c.frame, 1'699'999'999'123'456'000, "vcan0", line, sizeof line);
    std::printf("candump -L line: %s", line);
    std::printf("bytes:");
    for (std::size_t i = 0; i < 8; ++i) std::printf(" %02X", c.frame.data[i]);
    std::printf("\ncrc input (bytes 1..7 + data ID):");
    for (std::size_t i = 1; i < 8; ++i) std::printf(" %02X", c.frame.data[i]);
    std::printf(" %02X\ncrc: 0x%02X\n", e2e_data_id(c.frame.id), e2e_crc(c.frame, e2e_data_id(c.frame.id)));
    for (const auto& [name, value] : c.expect) std::printf("  %s = %g\n", name.c_str(), value);
    return 0;
  }
  std::fprintf(stderr, "usage: gvs_can_examples [--json|--candump|--sequence|--worked-example]\n");
  return 2;
}
