#include "dbc_file.hpp"

#include <fstream>
#include <regex>
#include <sstream>
#include <stdexcept>

namespace gvs::can::test {

const DbcMessage* DbcFile::find(const std::string& name) const {
  for (const DbcMessage& m : messages) {
    if (m.name == name) return &m;
  }
  return nullptr;
}

DbcFile read_dbc(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error("cannot open DBC " + path);
  static const std::regex bo(R"(^BO_ (\d+) (\w+) *: *(\d+) (\w+)\s*$)");
  static const std::regex sg(
      R"re(^\s+SG_ (\w+) *: *(\d+)\|(\d+)@([01])([+-]) \(([-+0-9.eE]+),([-+0-9.eE]+)\) \[([-+0-9.eE]+)\|([-+0-9.eE]+)\] "([^"]*)" +([\w,]+)\s*$)re");
  static const std::regex cycle(R"(^BA_ "GenMsgCycleTime" BO_ (\d+) (\d+);\s*$)");
  static const std::regex val(R"(^VAL_ (\d+) (\w+) (.*);\s*$)");
  static const std::regex val_item(R"re((-?\d+) "([^"]*)")re");
  static const std::regex cm_sg(R"re(^CM_ SG_ (\d+) (\w+) "([^"]*)";\s*$)re");
  DbcFile dbc;
  std::map<std::uint32_t, std::size_t> by_id;
  std::string line;
  int lineno = 0;
  DbcMessage* current = nullptr;
  std::smatch m;
  while (std::getline(in, line)) {
    ++lineno;
    if (std::regex_match(line, m, bo)) {
      DbcMessage msg;
      msg.id = static_cast<std::uint32_t>(std::stoul(m[1]));
      msg.name = m[2];
      msg.dlc = std::stoi(m[3]);
      msg.sender = m[4];
      by_id[msg.id] = dbc.messages.size();
      dbc.messages.push_back(msg);
      current = &dbc.messages.back();
    } else if (line.rfind(" SG_ ", 0) == 0 || line.rfind("\tSG_ ", 0) == 0) {
      if (current == nullptr || !std::regex_match(line, m, sg)) {
        throw std::runtime_error(path + ":" + std::to_string(lineno) + ": unexpected SG_ line: " + line);
      }
      DbcSignal s;
      s.name = m[1];
      s.start_bit = std::stoi(m[2]);
      s.length = std::stoi(m[3]);
      s.little_endian = m[4] == "1";
      s.is_signed = m[5] == "-";
      s.scale = std::stod(m[6]);
      s.offset = std::stod(m[7]);
      s.minimum = std::stod(m[8]);
      s.maximum = std::stod(m[9]);
      s.unit = m[10];
      current->signals.push_back(s);
    } else if (std::regex_match(line, m, cycle)) {
      dbc.messages.at(by_id.at(static_cast<std::uint32_t>(std::stoul(m[1])))).cycle_time_ms = std::stoi(m[2]);
    } else if (std::regex_match(line, m, val)) {
      DbcMessage& msg = dbc.messages.at(by_id.at(static_cast<std::uint32_t>(std::stoul(m[1]))));
      const std::string items = m[3];
      auto& table = msg.value_tables[m[2]];
      for (std::sregex_iterator it(items.begin(), items.end(), val_item), end; it != end; ++it) {
        table[std::stol((*it)[1])] = (*it)[2];
      }
    } else if (std::regex_match(line, m, cm_sg)) {
      dbc.messages.at(by_id.at(static_cast<std::uint32_t>(std::stoul(m[1])))).comments[m[2]] = m[3];
    } else if (line.empty() || line[0] != ' ') {
      current = nullptr;
    }
  }
  return dbc;
}

std::uint64_t dbc_get_bits(const std::uint8_t* data8, const DbcSignal& sig) {
  if (!sig.little_endian) throw std::runtime_error("test reader handles Intel byte order only: " + sig.name);
  std::uint64_t v = 0;
  for (int i = 0; i < sig.length; ++i) {
    const int bit = sig.start_bit + i;  // Intel: consecutive bits, LSB first
    const std::uint64_t b = (data8[bit / 8] >> (bit % 8)) & 1u;
    v |= b << i;
  }
  return v;
}

void dbc_set_bits(std::uint8_t* data8, const DbcSignal& sig, std::uint64_t bits) {
  for (int i = 0; i < sig.length; ++i) {
    const int bit = sig.start_bit + i;
    const auto mask = static_cast<std::uint8_t>(1u << (bit % 8));
    if ((bits >> i) & 1u) {
      data8[bit / 8] = static_cast<std::uint8_t>(data8[bit / 8] | mask);
    } else {
      data8[bit / 8] = static_cast<std::uint8_t>(data8[bit / 8] & ~mask);
    }
  }
}

double dbc_physical(const std::uint8_t* data8, const DbcSignal& sig) {
  const std::uint64_t bits = dbc_get_bits(data8, sig);
  double raw = static_cast<double>(bits);
  if (sig.is_signed && ((bits >> (sig.length - 1)) & 1u)) raw -= static_cast<double>(std::uint64_t{1} << sig.length);
  return raw * sig.scale + sig.offset;
}

}  // namespace gvs::can::test
