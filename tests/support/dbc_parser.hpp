#pragma once
// A small DBC reader for the tests: the version, the nodes (BU_), messages (BO_), signals (SG_), comments (CM_),
// message attributes (BA_ ... BO_) and value tables (VAL_) are enough to check the codec against the file and to
// decode frames the way a DBC tool (cantools, Vector) does. Host only; one statement per line, as estimator.dbc is
// written.
#include <cstdint>
#include <map>
#include <string>
#include <utility>
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
  std::string comment;  // CM_ SG_
};

struct DbcMessage {
  std::uint32_t id = 0;
  std::string name;
  unsigned dlc = 0;
  std::string sender;
  std::vector<DbcSignal> signals;
  std::string comment;                        // CM_ BO_
  std::map<std::string, std::string> attributes;  // BA_ "name" BO_ id value;  (value as written)
  const DbcSignal* signal(const std::string& name) const;
};

struct Dbc {
  std::string version;             // VERSION "..."
  std::vector<std::string> nodes;  // BU_
  std::string comment;             // the network's CM_ "..."
  std::vector<DbcMessage> messages;
  std::vector<std::pair<std::uint32_t, std::string>> value_tables;  // VAL_ id signal: (id, signal)
  std::vector<std::string> errors;  // lines that looked like a statement the reader knows but did not parse, or that
                                    // name a message or signal the file does not define
  const DbcMessage* message(std::uint32_t id) const;
  DbcMessage* message(std::uint32_t id);
};

Dbc parse_dbc(const std::string& text);
std::string read_text_file(const std::string& path);

// Bit positions (0..63, byte * 8 + bit) a signal occupies, in the DBC's own rules.
std::vector<unsigned> dbc_signal_bits(const DbcSignal& s);
// Physical value of a signal in 8 data bytes, in double, as a DBC tool computes it.
double dbc_decode(const DbcSignal& s, const std::uint8_t* data);

}  // namespace est::test
