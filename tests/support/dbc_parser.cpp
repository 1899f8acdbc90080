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

DbcMessage* Dbc::message(std::uint32_t id) {
  for (DbcMessage& m : messages)
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
  static const std::regex version(R"re(^VERSION\s+"([^"]*)"\s*$)re");
  static const std::regex cm_network(R"re(^CM_\s+"([^"]*)"\s*;\s*$)re");
  static const std::regex cm_message(R"re(^CM_\s+BO_\s+(\d+)\s+"([^"]*)"\s*;\s*$)re");
  static const std::regex cm_signal(R"re(^CM_\s+SG_\s+(\d+)\s+(\w+)\s+"([^"]*)"\s*;\s*$)re");
  static const std::regex ba_message(R"re(^BA_\s+"(\w+)"\s+BO_\s+(\d+)\s+([^;\s]+)\s*;\s*$)re");
  static const std::regex val(R"re(^VAL_\s+(\d+)\s+(\w+)\s+.*;\s*$)re");
  Dbc dbc;
  std::istringstream lines(text);
  std::string line;
  // Comments and attributes may come before the message they name is known: kept and applied at the end.
  std::vector<std::string> later_lines;
  while (std::getline(lines, line)) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    std::smatch m;
    if (line.rfind("VERSION", 0) == 0) {
      if (std::regex_match(line, m, version))
        dbc.version = m[1];
      else
        dbc.errors.push_back(line);
    } else if (line.rfind("BU_", 0) == 0) {
      std::istringstream names(line.substr(line.find(':') == std::string::npos ? 3 : line.find(':') + 1));
      std::string n;
      while (names >> n) dbc.nodes.push_back(n);
    } else if (line.rfind("CM_ ", 0) == 0 || line.rfind("BA_ ", 0) == 0 || line.rfind("VAL_ ", 0) == 0) {
      later_lines.push_back(line);
    } else if (line.rfind("BO_ ", 0) == 0) {
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
  for (const std::string& l : later_lines) {
    std::smatch m;
    if (std::regex_match(l, m, cm_network)) {
      dbc.comment = m[1];
    } else if (std::regex_match(l, m, cm_message)) {
      DbcMessage* msg = dbc.message(static_cast<std::uint32_t>(std::stoul(m[1])));
      if (msg == nullptr)
        dbc.errors.push_back(l);
      else
        msg->comment = m[2];
    } else if (std::regex_match(l, m, cm_signal)) {
      DbcMessage* msg = dbc.message(static_cast<std::uint32_t>(std::stoul(m[1])));
      DbcSignal* sig = nullptr;
      if (msg != nullptr)
        for (DbcSignal& s : msg->signals)
          if (s.name == m[2]) sig = &s;
      if (sig == nullptr)
        dbc.errors.push_back(l);
      else
        sig->comment = m[3];
    } else if (std::regex_match(l, m, ba_message)) {
      DbcMessage* msg = dbc.message(static_cast<std::uint32_t>(std::stoul(m[2])));
      if (msg == nullptr)
        dbc.errors.push_back(l);
      else
        msg->attributes[m[1]] = m[3];
    } else if (std::regex_match(l, m, val)) {
      const auto id = static_cast<std::uint32_t>(std::stoul(m[1]));
      const DbcMessage* msg = dbc.message(id);
      if (msg == nullptr || msg->signal(m[2]) == nullptr)
        dbc.errors.push_back(l);
      else
        dbc.value_tables.emplace_back(id, m[2]);
    } else if (l.rfind("CM_ ", 0) == 0 || l.rfind("VAL_ ", 0) == 0) {
      dbc.errors.push_back(l);  // a comment or value table of a kind this reader does not know
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
