// DBC reader for the tests (dbc_parser.hpp).
#include "dbc_parser.hpp"

#include <fstream>
#include <regex>
#include <sstream>

namespace est::test {

const DbcSignal* DbcMessage::signal(const std::string& n) const {
  for (const DbcSignal& s : signals)
    if (s.name == n) return &s;
  return nullptr;
}

const DbcMessage* Dbc::message(std::uint32_t id) const {
  for (const DbcMessage& m : messages)
    if (m.id == id) return &m;
  return nullptr;
}

std::string read_text_file(const std::string& path) {
  std::ifstream in(path);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

Dbc parse_dbc(const std::string& text) {
  static const std::regex bo(R"(^BO_\s+(\d+)\s+(\w+)\s*:\s*(\d+)\s+(\w+)\s*$)");
  static const std::regex sg(
      R"re(^\s+SG_\s+(\w+)\s*(\w*)\s*:\s*(\d+)\|(\d+)@([01])([+-])\s*\(\s*([^,\s]+)\s*,\s*([^)\s]+)\s*\)\s*)re"
      R"re(\[\s*([^|\s]+)\s*\|\s*([^\]\s]+)\s*\]\s*"([^"]*)"\s*(.*)$)re");
  Dbc dbc;
  std::istringstream lines(text);
  std::string line;
  while (std::getline(lines, line)) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    std::smatch m;
    if (line.rfind("BO_ ", 0) == 0) {
      if (!std::regex_match(line, m, bo)) {
        dbc.errors.push_back(line);
        continue;
      }
      DbcMessage msg;
      msg.id = static_cast<std::uint32_t>(std::stoul(m[1]));
      msg.name = m[2];
      msg.dlc = static_cast<unsigned>(std::stoul(m[3]));
      msg.sender = m[4];
      dbc.messages.push_back(msg);
    } else if (line.find("SG_ ") != std::string::npos && line.rfind(" ", 0) == 0) {
      if (!std::regex_match(line, m, sg) || dbc.messages.empty()) {
        dbc.errors.push_back(line);
        continue;
      }
      DbcSignal s;
      s.name = m[1];
      s.start_bit = static_cast<unsigned>(std::stoul(m[3]));
      s.length = static_cast<unsigned>(std::stoul(m[4]));
      s.little_endian = m[5] == "1";
      s.is_signed = m[6] == "-";
      s.factor = std::stod(m[7]);
      s.offset = std::stod(m[8]);
      s.minimum = std::stod(m[9]);
      s.maximum = std::stod(m[10]);
      s.unit = m[11];
      std::istringstream rx(m[12].str());
      std::string r;
      while (std::getline(rx, r, ',')) {
        r.erase(0, r.find_first_not_of(' '));
        r.erase(r.find_last_not_of(' ') + 1);
        if (!r.empty()) s.receivers.push_back(r);
      }
      dbc.messages.back().signals.push_back(s);
    }
  }
  return dbc;
}

std::vector<unsigned> dbc_signal_bits(const DbcSignal& s) {
  std::vector<unsigned> bits;
  if (s.little_endian) {
    for (unsigned i = 0; i < s.length; ++i) bits.push_back(s.start_bit + i);
  } else {
    // Motorola: start bit is the MSB; the next bit is one lower in the byte, or bit 7 of the next byte.
    unsigned pos = s.start_bit;
    for (unsigned i = 0; i < s.length; ++i) {
      bits.push_back(pos);
      pos = (pos % 8 == 0) ? pos + 15 : pos - 1;
    }
  }
  return bits;
}

double dbc_decode(const DbcSignal& s, const std::uint8_t* data) {
  const std::vector<unsigned> bits = dbc_signal_bits(s);
  std::uint64_t raw = 0;
  // bits are listed LSB first for Intel, MSB first for Motorola.
  for (std::size_t i = 0; i < bits.size(); ++i) {
    const std::uint64_t b = (static_cast<unsigned>(data[bits[i] / 8]) >> (bits[i] % 8)) & 1u;
    if (s.little_endian)
      raw |= b << i;
    else
      raw = (raw << 1) | b;
  }
  double value = static_cast<double>(raw);
  if (s.is_signed && s.length < 64 && (raw >> (s.length - 1)) & 1u)
    value = static_cast<double>(static_cast<std::int64_t>(raw) - (std::int64_t{1} << s.length));
  return value * s.factor + s.offset;
}

}  // namespace est::test
