// docs/can-interface.md shows a worked example frame; it must be the frame
// the code computes.
#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <sstream>

#include "example_cases.hpp"
#include "gvs/can/candump.hpp"
#include "gvs/can/e2e.hpp"

namespace gvs::can {
namespace {

TEST(DocsWorkedExample, DocumentShowsTheFrameTheCodeComputes) {
  std::ifstream in(GVS_CAN_DOC);
  ASSERT_TRUE(in) << "cannot read " << GVS_CAN_DOC;
  std::stringstream doc;
  doc << in.rdbuf();
  const std::string text = doc.str();

  const CanFrame f = encode_velocity(test::worked_example_velocity(), MessageIds{}, test::kWorkedExampleCounter);
  char line[kCandumpLineMax + 1];
  format_candump_line(f, 1'699'999'999'123'456'000, "vcan0", line, sizeof line);
  std::string expected_line(line);
  expected_line.pop_back();  // '\n'
  EXPECT_NE(text.find(expected_line), std::string::npos) << "docs lack: " << expected_line;

  char crc_input[64];
  std::snprintf(crc_input, sizeof crc_input, "%02X %02X %02X %02X %02X %02X %02X %02X", f.data[1], f.data[2],
                f.data[3], f.data[4], f.data[5], f.data[6], f.data[7], e2e_data_id(f.id));
  EXPECT_NE(text.find(crc_input), std::string::npos) << "docs lack the CRC input: " << crc_input;
  char crc[16];
  std::snprintf(crc, sizeof crc, "0x%02X", f.data[0]);
  EXPECT_NE(text.find(std::string("CRC = ") + crc), std::string::npos) << "docs lack: CRC = " << crc;
}

}  // namespace
}  // namespace gvs::can
