#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <random>
#include <sstream>
#include <stdexcept>
#include <string>

#include <linux/can/error.h>
#include <unistd.h>

#include "gvs/can/candump.hpp"
#include "gvs/can/codec.hpp"
#include "gvs/can/sink.hpp"
#include "gvs/can/socketcan_sink.hpp"

namespace gvs::can {
namespace {

std::string line_of(const CanFrame& f, std::int64_t t_ns, std::string_view iface = "vcan0") {
  char buf[kCandumpLineMax + 1];
  const std::size_t n = format_candump_line(f, t_ns, iface, buf, sizeof buf);
  return std::string(buf, n);
}

CanFrame frame(std::uint32_t id, std::initializer_list<std::uint8_t> bytes) {
  CanFrame f;
  f.id = id;
  for (std::uint8_t b : bytes) f.data[f.len++] = b;
  return f;
}

TEST(CandumpFormat, ExactlyLikeCandumpL) {
  EXPECT_EQ(line_of(frame(0x123, {0x00, 0x11, 0x22, 0x33, 0x44, 0x55, 0x66, 0x77}), 1'699'999'999'123'456'789),
            "(1699999999.123456) vcan0 123#0011223344556677\n");
  EXPECT_EQ(line_of(frame(0x7, {0xAB, 0xCD}), 5'000'001'000, "can1"), "(0000000005.000001) can1 007#ABCD\n");
  EXPECT_EQ(line_of(frame(0x300, {}), 0), "(0000000000.000000) vcan0 300#\n");
  CanFrame ext = frame(0x1ABCDEF, {0xFE});
  ext.extended = true;
  EXPECT_EQ(line_of(ext, 0), "(0000000000.000000) vcan0 01ABCDEF#FE\n");
  CanFrame rtr = frame(0x10, {});
  rtr.remote = true;
  rtr.len = 4;
  EXPECT_EQ(line_of(rtr, 0), "(0000000000.000000) vcan0 010#R4\n");
  CanFrame err = frame(CAN_ERR_BUSOFF, {0, 0, 0, 0, 0, 0, 0, 0});
  err.error = true;
  EXPECT_EQ(line_of(err, 0), "(0000000000.000000) vcan0 20000040#0000000000000000\n");
}

TEST(CandumpParse, RoundTripsEveryKindOfFrame) {
  std::mt19937 rng(7);
  for (int i = 0; i < 500; ++i) {
    CanFrame f;
    const int kind = i % 4;
    f.extended = kind == 1;
    f.remote = kind == 2;
    f.error = kind == 3;
    f.id = static_cast<std::uint32_t>(rng()) & (f.extended ? 0x1FFFFFFFu : f.error ? 0x1FFu : 0x7FFu);
    f.len = static_cast<std::uint8_t>(rng() % 9);
    if (!f.remote) {
      for (std::size_t k = 0; k < f.len; ++k) f.data[k] = static_cast<std::uint8_t>(rng());
    }
    const std::int64_t t = static_cast<std::int64_t>(rng()) * 1000;
    const std::string line = line_of(f, t, "gvs0");
    const auto parsed = parse_candump_line(line);
    ASSERT_TRUE(parsed) << line;
    EXPECT_EQ(parsed->t_ns, t);
    EXPECT_EQ(parsed->iface, "gvs0");
    EXPECT_EQ(parsed->frame.id, f.id) << line;
    EXPECT_EQ(parsed->frame.extended, f.extended);
    EXPECT_EQ(parsed->frame.remote, f.remote);
    EXPECT_EQ(parsed->frame.error, f.error);
    EXPECT_EQ(parsed->frame.len, f.len);
    EXPECT_EQ(parsed->frame.data, f.data) << line;
  }
}

TEST(CandumpParse, AcceptsCandumpVariantsRejectsJunk) {
  auto p = parse_candump_line("(1700000000.5) can0 300#11.22.33");
  ASSERT_TRUE(p);
  EXPECT_EQ(p->t_ns, 1'700'000'000'500'000'000);
  EXPECT_EQ(p->frame.len, 3);
  EXPECT_EQ(p->frame.data[2], 0x33);
  EXPECT_TRUE(parse_candump_line("(1.000000) can0 300#0011\r\n"));
  EXPECT_FALSE(parse_candump_line(""));
  EXPECT_FALSE(parse_candump_line("# comment"));
  EXPECT_FALSE(parse_candump_line("(1.0) can0 300##10011"));  // CAN FD
  EXPECT_FALSE(parse_candump_line("(1.0) can0 800#00"));      // > 11 bit in 3 digits
  EXPECT_FALSE(parse_candump_line("(1.0) can0 3000#00"));     // 4 digits
  EXPECT_FALSE(parse_candump_line("(1.0) can0 300#001"));     // odd nibble
  EXPECT_FALSE(parse_candump_line("(1.0) can0 300#000000000000000000"));  // 9 bytes
  EXPECT_FALSE(parse_candump_line("(1.0) can0 300#00 junk"));
  EXPECT_FALSE(parse_candump_line("(1.0) can0"));
  EXPECT_FALSE(parse_candump_line("(1.0)"));
  EXPECT_FALSE(parse_candump_line("(99999999999999999999.0) can0 300#00"));
  EXPECT_FALSE(parse_candump_line("(1.0) averyveryverylongname0 300#00"));
}

TEST(CandumpParse, SurvivesArbitraryBytes) {
  std::mt19937 rng(1234);
  const std::string good = "(1699999999.123456) vcan0 300#0011223344556677";
  for (int i = 0; i < 20000; ++i) {
    std::string s = good;
    const int edits = 1 + static_cast<int>(rng() % 4);
    for (int k = 0; k < edits; ++k) {
      const std::size_t pos = rng() % (s.size() + 1);
      switch (rng() % 3) {
        case 0: if (pos < s.size()) s[pos] = static_cast<char>(rng()); break;
        case 1: s.insert(pos, 1, static_cast<char>(rng())); break;
        default: s = s.substr(0, pos); break;
      }
    }
    const auto p = parse_candump_line(s);
    if (p) {
      EXPECT_LE(p->frame.len, 8);
    }
  }
}

std::int64_t fixed_clock() { return 1'699'999'999'123'456'000; }

TEST(CandumpSink, WritesCandumpLinesToAFile) {
  const std::string path = testing::TempDir() + "gvs_candump_sink_test.log";
  {
    CandumpSink sink(path, "vcan0", &fixed_clock);
    Encoder enc({});
    EXPECT_EQ(sink.send(enc.velocity({})), SendResult::Ok);
    EXPECT_EQ(sink.send(frame(0x123, {0x00, 0x11, 0x22, 0x33, 0x44, 0x55, 0x66, 0x77})), SendResult::Ok);
    SinkEvent events[4];
    EXPECT_EQ(sink.poll_events(events), 0u);
    EXPECT_EQ(sink.counters().frames_sent, 2u);
    EXPECT_EQ(sink.take_fault_bits(), 0);
    EXPECT_EQ(sink.description(), "candump:" + path);
  }
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  Encoder enc({});
  const std::string first = line_of(enc.velocity({}), fixed_clock());
  EXPECT_EQ(text.str(), first + "(1699999999.123456) vcan0 123#0011223344556677\n");
  std::remove(path.c_str());
}

TEST(CandumpSink, SetupErrorNamesTheFile) {
  try {
    CandumpSink sink("/nonexistent-dir/x.log");
    FAIL();
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent-dir/x.log"), std::string::npos) << e.what();
  }
}

TEST(SinkUri, ParsesBothSchemes) {
  SinkUri u = parse_sink_uri("socketcan:vcan0");
  EXPECT_EQ(u.kind, SinkUri::Kind::SocketCan);
  EXPECT_EQ(u.target, "vcan0");
  u = parse_sink_uri("candump:-");
  EXPECT_EQ(u.kind, SinkUri::Kind::Candump);
  EXPECT_EQ(u.target, "-");
  u = parse_sink_uri("candump:/var/log/gvs:run1.log");
  EXPECT_EQ(u.target, "/var/log/gvs:run1.log");
  for (const char* bad : {"vcan0", "socketcan:", "candump:", "udp:x", "socketcan:can/0",
                          "socketcan:averyveryverylongname", "socketcan:can 0", ""}) {
    EXPECT_THROW(parse_sink_uri(bad), std::invalid_argument) << bad;
  }
  try {
    parse_sink_uri("udp:x");
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("socketcan:IFACE"), std::string::npos);
  }
}

TEST(SinkUri, OpenSinkCandumpStdoutAndFile) {
  auto sink = open_sink("candump:-");
  EXPECT_EQ(sink->description(), "candump:-");
  const std::string path = testing::TempDir() + "gvs_open_sink_test.log";
  SinkOptions opt;
  opt.candump_interface = "gvs0";
  auto file_sink = open_sink("candump:" + path, opt);
  EXPECT_EQ(file_sink->send(frame(0x1, {1})), SendResult::Ok);
  file_sink.reset();
  std::ifstream in(path);
  std::string line;
  std::getline(in, line);
  EXPECT_NE(line.find(" gvs0 001#01"), std::string::npos) << line;
  std::remove(path.c_str());
}

// On a machine without the interface (or without CAN in the kernel, as on
// the CI container) the setup error names the interface and says what to do.
TEST(SocketCanSink, SetupErrorNamesTheInterface) {
  try {
    SocketCanSink sink("gvsnosuch0");
    FAIL() << "an interface named gvsnosuch0 exists?";
  } catch (const std::runtime_error& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("gvsnosuch0"), std::string::npos) << msg;
    EXPECT_TRUE(msg.find("modprobe") != std::string::npos || msg.find("ip link add") != std::string::npos) << msg;
  }
  EXPECT_THROW(SocketCanSink("this-name-is-too-long"), std::invalid_argument);
}

}  // namespace
}  // namespace gvs::can
