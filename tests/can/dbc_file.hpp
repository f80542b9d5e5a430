// A small DBC reader for the tests: messages, signals, value tables and
// cycle times, enough to cross-check can/gvs.dbc against the codec.
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace gvs::can::test {

struct DbcSignal {
  std::string name;
  int start_bit = 0;
  int length = 0;
  bool little_endian = true;  ///< @1
  bool is_signed = false;     ///< '-'
  double scale = 1.0;
  double offset = 0.0;
  double minimum = 0.0;
  double maximum = 0.0;
  std::string unit;
};

struct DbcMessage {
  std::uint32_t id = 0;
  std::string name;
  int dlc = 0;
  std::string sender;
  int cycle_time_ms = -1;
  std::vector<DbcSignal> signals;
  std::map<std::string, std::map<long, std::string>> value_tables;  ///< signal -> value -> text
  std::map<std::string, std::string> comments;                      ///< signal -> CM_ text
};

struct DbcFile {
  std::vector<DbcMessage> messages;
  [[nodiscard]] const DbcMessage* find(const std::string& name) const;
};

/// Parses the file; throws std::runtime_error with the line number on a
/// line it does not understand inside a BO_ block.
DbcFile read_dbc(const std::string& path);

/// Independent bit access from a DBC signal (Intel byte order only).
std::uint64_t dbc_get_bits(const std::uint8_t* data8, const DbcSignal& sig);
void dbc_set_bits(std::uint8_t* data8, const DbcSignal& sig, std::uint64_t bits);
double dbc_physical(const std::uint8_t* data8, const DbcSignal& sig);

}  // namespace gvs::can::test
