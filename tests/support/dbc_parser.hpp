#pragma once
// A small DBC reader for the tests: messages (BO_), signals (SG_), comments and value tables are enough to check
// the codec against the file and to decode frames the way a DBC tool (cantools, Vector) does. Host only.
#include <cstdint>
#include <string>
#include <vector>

namespace est::test {

struct DbcSignal {
  std::string name;
  unsigned start_bit = 0;
  unsigned length = 0;
  bool little_endian = true;  // @1
  bool is_signed = false;     // -
  double factor = 1.0;
  double offset = 0.0;
  double minimum = 0.0;
  double maximum = 0.0;
  std::string unit;
  std::vector<std::string> receivers;
};

struct DbcMessage {
  std::uint32_t id = 0;
  std::string name;
  unsigned dlc = 0;
  std::string sender;
  std::vector<DbcSignal> signals;
  const DbcSignal* signal(const std::string& name) const;
};

struct Dbc {
  std::vector<DbcMessage> messages;
  std::vector<std::string> errors;  // lines that looked like BO_/SG_ but did not parse
  const DbcMessage* message(std::uint32_t id) const;
};

Dbc parse_dbc(const std::string& text);
std::string read_text_file(const std::string& path);

// Bit positions (0..63, byte * 8 + bit) a signal occupies, in the DBC's own rules.
std::vector<unsigned> dbc_signal_bits(const DbcSignal& s);
// Physical value of a signal in 8 data bytes, in double, as a DBC tool computes it.
double dbc_decode(const DbcSignal& s, const std::uint8_t* data);

}  // namespace est::test
