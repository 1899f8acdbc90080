// candump log lines (hal/can/candump.hpp): what a frame formats to, that every frame and stamp comes back from its
// line (to the microsecond the format keeps), and that every malformed field is refused with its reason.
#include <catch2/catch.hpp>

#include <cstdint>
#include <cstring>
#include <string>

#include "hal/can/candump.hpp"

using hal::can::CandumpStatus;
using hal::can::CanFrame;
using hal::TimeNs;

namespace {

std::string format(const CanFrame& f, TimeNs stamp, const char* iface = "vcan0") {
  char line[hal::can::kCandumpLineMax];
  const std::size_t n = hal::can::format_candump_line(f, stamp, iface, line);
  REQUIRE(n <= hal::can::kCandumpLineMax);
  return std::string(line, n);
}

CandumpStatus parse(const std::string& line, CanFrame& f, TimeNs& stamp) {
  return hal::can::parse_candump_line(line.data(), line.size(), f, stamp);
}

CandumpStatus status_of(const std::string& line) {
  CanFrame f;
  TimeNs t = 0;
  return parse(line, f, t);
}

CanFrame frame(std::uint32_t id, std::initializer_list<std::uint8_t> data) {
  CanFrame f;
  f.id = id;
  f.dlc = static_cast<std::uint8_t>(data.size());
  std::copy(data.begin(), data.end(), f.data);
  return f;
}

}  // namespace

TEST_CASE("a frame formats as candump -l writes it: (seconds.micros) iface id#data", "[candump]") {
  CHECK(format(frame(0x100, {1, 2, 3, 4, 5, 6, 7, 8}), 1436509052249713000) ==
        "(1436509052.249713) vcan0 100#0102030405060708\n");
  CHECK(format(frame(0x7FF, {0xAB, 0xCD}), 5000, "can0") == "(0.000005) can0 7FF#ABCD\n");
  CHECK(format(frame(0x001, {}), 2 * hal::kNsPerS) == "(2.000000) vcan0 001#\n");  // no data bytes
  CHECK(format(frame(0x010, {0}), 999) == "(0.000000) vcan0 010#00\n");           // below a microsecond: cut
  CHECK(format(frame(0x010, {0}), -5) == "(0.000000) vcan0 010#00\n");            // before the epoch: 0
  // The interface name is cut to 15 characters.
  CHECK(format(frame(0x123, {1}), 0, "a_very_long_interface_name") == "(0.000000) a_very_long_int 123#01\n");
  // A DLC beyond 8 (not a classic frame) writes 8 bytes at most.
  CanFrame f = frame(0x123, {1, 2, 3, 4, 5, 6, 7, 8});
  f.dlc = 15;
  CHECK(format(f, 0) == "(0.000000) vcan0 123#0102030405060708\n");
}

TEST_CASE("every frame comes back from its line, with its stamp to the microsecond", "[candump]") {
  for (std::uint32_t id : {0x000u, 0x100u, 0x104u, 0x112u, 0x310u, 0x7FFu})
    for (std::uint8_t dlc = 0; dlc <= 8; ++dlc)
      for (TimeNs stamp : {TimeNs{0}, TimeNs{1}, TimeNs{1500000000}, TimeNs{1436509052249713123},
                           TimeNs{9223372035999999999}}) {
        CanFrame f;
        f.id = id;
        f.dlc = dlc;
        for (std::uint8_t k = 0; k < dlc; ++k) f.data[k] = static_cast<std::uint8_t>(0x11u * k + id);
        const std::string line = format(f, stamp);
        REQUIRE(line.back() == '\n');
        CanFrame g;
        TimeNs back = -1;
        INFO(line);
        REQUIRE(parse(line.substr(0, line.size() - 1), g, back) == CandumpStatus::ok);
        CHECK(g.id == id);
        CHECK(g.dlc == dlc);
        CHECK(std::memcmp(g.data, f.data, dlc) == 0);
        CHECK(back == stamp - stamp % 1000);
      }
}

TEST_CASE("lines as tools write them parse: lowercase hex, trailing CR and spaces, leading spaces", "[candump]") {
  CanFrame f;
  TimeNs t = 0;
  REQUIRE(parse("(1.250000) can0 10a#deadBEEF\r", f, t) == CandumpStatus::ok);
  CHECK(f.id == 0x10A);
  CHECK(f.dlc == 4);
  CHECK(f.data[0] == 0xDE);
  CHECK(f.data[3] == 0xEF);
  CHECK(t == 1250000000);
  REQUIRE(parse("   (7.000001) vcan0 100#01   ", f, t) == CandumpStatus::ok);
  CHECK(t == 7000001000);
  CHECK(f.dlc == 1);
}

TEST_CASE("blank lines and comments are blank, not errors", "[candump]") {
  CHECK(status_of("") == CandumpStatus::blank);
  CHECK(status_of("   ") == CandumpStatus::blank);
  CHECK(status_of("\r") == CandumpStatus::blank);
  CHECK(status_of("# recorded on the rig") == CandumpStatus::blank);
  CHECK(status_of("  # indented comment") == CandumpStatus::blank);
}

TEST_CASE("a malformed stamp is refused as bad_stamp", "[candump]") {
  for (const char* line : {
           "1.000000) vcan0 100#01",                 // no '('
           "() vcan0 100#01",                        // no seconds
           "(.000000) vcan0 100#01",                 // no seconds before the point
           "(1) vcan0 100#01",                       // no point
           "(1.00000) vcan0 100#01",                 // five digits of microseconds
           "(1.0000000) vcan0 100#01",               // seven
           "(1.000000 vcan0 100#01",                 // no ')'
           "(-1.000000) vcan0 100#01",               // negative
           "(1x.000000) vcan0 100#01",               // not a number
           "(1234567890123.000000) vcan0 100#01",    // more than 12 digits of seconds
           "(9223372037.000000) vcan0 100#01",       // beyond int64 nanoseconds
           "(999999999999.999999) vcan0 100#01",     // ditto, twelve digits
       }) {
    INFO(line);
    CHECK(status_of(line) == CandumpStatus::bad_stamp);
  }
  CHECK(status_of("(9223372035.999999) vcan0 100#01") == CandumpStatus::ok);  // the largest that fits
}

TEST_CASE("a malformed interface is refused as bad_interface", "[candump]") {
  for (const char* line : {
           "(1.000000)vcan0 100#01",                 // no space after the stamp
           "(1.000000)  100#01",                     // an empty name
           "(1.000000) sixteen_chars_ifc 100#01",    // longer than 15
           "(1.000000) vcan0",                       // nothing after the name
       }) {
    INFO(line);
    CHECK(status_of(line) == CandumpStatus::bad_interface);
  }
}

TEST_CASE("a malformed or foreign id is refused as bad_id", "[candump]") {
  for (const char* line : {
           "(1.000000) vcan0 10#01",        // two digits
           "(1.000000) vcan0 1000#01",      // four: not an 11-bit id of this bus
           "(1.000000) vcan0 12345678#01",  // an extended id
           "(1.000000) vcan0 1G0#01",       // not hex
           "(1.000000) vcan0 800#01",       // beyond 11 bits
           "(1.000000) vcan0 100",          // no '#'
           "(1.000000) vcan0 #01",          // no id at all
       }) {
    INFO(line);
    CHECK(status_of(line) == CandumpStatus::bad_id);
  }
}

TEST_CASE("malformed data is refused as bad_data", "[candump]") {
  for (const char* line : {
           "(1.000000) vcan0 100#012",                 // an odd number of digits
           "(1.000000) vcan0 100#01GG",                // not hex
           "(1.000000) vcan0 100#010203040506070809",  // nine bytes: not a classic frame
           "(1.000000) vcan0 100##10102",              // CAN FD
           "(1.000000) vcan0 100#R",                   // a remote frame
           "(1.000000) vcan0 100#01 02",               // a space inside
       }) {
    INFO(line);
    CHECK(status_of(line) == CandumpStatus::bad_data);
  }
}

TEST_CASE("a refused line leaves the frame as it was, and every status has a name", "[candump]") {
  CanFrame f = frame(0x42, {9});
  TimeNs t = 77;
  REQUIRE(parse("(1.000000) vcan0 100#012", f, t) == CandumpStatus::bad_data);
  CHECK(f.id == 0x42);
  CHECK(f.dlc == 1);
  CHECK(std::string(hal::can::to_string(CandumpStatus::ok)) == "ok");
  CHECK(std::string(hal::can::to_string(CandumpStatus::blank)) == "blank");
  CHECK(std::string(hal::can::to_string(CandumpStatus::bad_stamp)) == "bad_stamp");
  CHECK(std::string(hal::can::to_string(CandumpStatus::bad_interface)) == "bad_interface");
  CHECK(std::string(hal::can::to_string(CandumpStatus::bad_id)) == "bad_id");
  CHECK(std::string(hal::can::to_string(CandumpStatus::bad_data)) == "bad_data");
}
