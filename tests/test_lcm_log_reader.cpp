// hal/lcm/lcm_log_reader.hpp: LCM log files read back whole, and every way a file can be bad said with its place.
#include <catch2/catch.hpp>
#include <lcm/lcm-cpp.hpp>

#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>
#include <unistd.h>

#include "hal/lcm/lcm_log_reader.hpp"

using hal::lcm::LcmLogEvent;
using hal::lcm::LcmLogReader;
using hal::lcm::LogProblemKind;

namespace {

// Three events written by liblcm's own writer, returned as the file's bytes.
std::string liblcm_log() {
  const std::string path = "/tmp/test_lcm_log_reader_" + std::to_string(::getpid()) + ".lcmlog";
  {
    ::lcm::LogFile log(path, "w");
    const char* channels[] = {"EST_WHEEL_TICKS", "EST_RANGE_SCAN", "EST_STEERING"};
    for (int i = 0; i < 3; ++i) {
      std::string payload(static_cast<std::size_t>(10 + 100 * i), static_cast<char>('a' + i));
      ::lcm::LogEvent e{};
      e.timestamp = 1000 * (i + 1);
      e.channel = channels[i];
      e.datalen = static_cast<std::int32_t>(payload.size());
      e.data = payload.data();
      REQUIRE(log.writeEvent(&e) == 0);
    }
  }
  std::ifstream in(path, std::ios::binary);
  std::ostringstream ss;
  ss << in.rdbuf();
  std::remove(path.c_str());
  return ss.str();
}

struct Read {
  std::vector<LcmLogEvent> events;
  std::vector<hal::lcm::LogProblem> problems;
  bool refused = false;
  std::uint64_t truncated = 0, bad_sync = 0, oversize = 0, not_a_log = 0;
};

Read read_all(const std::string& bytes) {
  std::istringstream in(bytes);
  LcmLogReader r(in);
  Read out;
  LcmLogEvent e;
  while (r.next(e)) out.events.push_back(e);
  out.problems = r.problems();
  out.refused = r.refused();
  out.truncated = r.count(LogProblemKind::truncated);
  out.bad_sync = r.count(LogProblemKind::bad_sync);
  out.oversize = r.count(LogProblemKind::oversize);
  out.not_a_log = r.count(LogProblemKind::not_a_log);
  return out;
}

// Offsets of the three events: 28-byte header, channel, data.
constexpr std::size_t kEvent2 = 28 + 15 + 10;
constexpr std::size_t kEvent3 = kEvent2 + 28 + 14 + 110;

}  // namespace

TEST_CASE("a log written by liblcm reads back whole, with channels, stamps and payloads") {
  const std::string bytes = liblcm_log();
  const Read r = read_all(bytes);
  REQUIRE(r.events.size() == 3);
  CHECK(r.problems.empty());
  CHECK_FALSE(r.refused);
  CHECK(r.events[1].channel == "EST_RANGE_SCAN");
  CHECK(r.events[1].timestamp_us == 2000);
  CHECK(r.events[1].size() == 110);
  CHECK(r.events[1].data[0] == 'b');
  CHECK(r.events[1].offset == kEvent2);
  CHECK(r.events[2].offset == kEvent3);
}

TEST_CASE("random bytes are refused as not an LCM log, and nothing is read from them") {
  std::string junk(5000, '\0');
  std::uint32_t x = 12345;
  for (char& c : junk) {
    x = x * 1664525u + 1013904223u;
    c = static_cast<char>(x >> 24);
  }
  // liblcm's reader would skip to a sync word anywhere in the file: one is hidden in the middle.
  const std::string log = liblcm_log();
  junk.replace(2000, log.size(), log);
  const Read r = read_all(junk);
  CHECK(r.events.empty());
  CHECK(r.refused);
  CHECK(r.not_a_log == 1);
  REQUIRE(r.problems.size() == 1);
  CHECK(hal::lcm::describe(r.problems[0]).find("not an LCM log") != std::string::npos);
}

TEST_CASE("an empty file has no event and no problem, and read_lcm_log refuses it") {
  const Read r = read_all("");
  CHECK(r.events.empty());
  CHECK(r.problems.empty());
  CHECK_THROWS_WITH(hal::lcm::read_lcm_log("/nonexistent/x.lcmlog", "t", nullptr, [](const LcmLogEvent&) {}),
                    Catch::Contains("/nonexistent/x.lcmlog: cannot open"));
}

TEST_CASE("a log cut in the middle of an event gives the events before the cut and says where it was cut") {
  const std::string bytes = liblcm_log();
  const std::size_t cut = kEvent3 - 50;  // inside event 2's payload
  const Read r = read_all(bytes.substr(0, cut));
  REQUIRE(r.events.size() == 1);
  CHECK(r.truncated == 1);
  REQUIRE(r.problems.size() == 1);
  CHECK(r.problems[0].offset == cut);
  CHECK(r.problems[0].event == 2);
  CHECK(hal::lcm::describe(r.problems[0]) ==
        "truncated at byte " + std::to_string(cut) + ", in event 2 (channel EST_RANGE_SCAN): " +
            std::to_string(cut - kEvent2) + " of 152 bytes present");

  SECTION("a cut inside a header has no channel to name") {
    const Read h = read_all(bytes.substr(0, kEvent2 + 10));
    CHECK(h.events.size() == 1);
    REQUIRE(h.problems.size() == 1);
    CHECK(h.problems[0].kind == LogProblemKind::truncated);
    CHECK(h.problems[0].channel.empty());
    CHECK(h.problems[0].present == 10);
  }
}

TEST_CASE("a bad sync word between events is reported and the reader goes on at the next sync word") {
  std::string bytes = liblcm_log();
  bytes.insert(kEvent2, "garbage");
  const Read r = read_all(bytes);
  CHECK(r.events.size() == 3);
  CHECK(r.bad_sync == 1);
  REQUIRE(r.problems.size() == 1);
  CHECK(r.problems[0].offset == kEvent2);
  CHECK(r.problems[0].present == 7);
  CHECK(r.events[1].offset == kEvent2 + 7);
}

TEST_CASE("an impossible length skips the event and says which length") {
  std::string bytes = liblcm_log();
  bytes[kEvent2 + 24] = static_cast<char>(0x7f);  // data length of event 2 > 2 GB
  const Read r = read_all(bytes);
  CHECK(r.oversize == 1);
  REQUIRE_FALSE(r.problems.empty());
  CHECK(r.problems[0].offset == kEvent2);
  CHECK(r.problems[0].length > hal::lcm::kMaxLogDataBytes);
  CHECK(r.events.size() == 2);  // events 1 and 3
  CHECK(r.events[1].channel == "EST_STEERING");
}

TEST_CASE("a header claiming the largest payload in a short file is a cut, and allocates only what the file holds") {
  // Found by tests/fuzz/fuzz_lcm_log: each such input allocated 64 MB (340 inputs/s instead of thousands).
  std::string bytes = liblcm_log().substr(0, kEvent2);
  const char header[] = {'\xed', '\xa1', '\xda', '\x01', 0, 0, 0, 0, 0, 0, 0, 9, 0, 0, 0, 0, 0, 0, 0, 0,
                         0,      0,      0,      1,      '\x04', 0, 0, 0};  // channel 1 byte, data 64 MiB
  bytes.append(header, sizeof header);
  bytes += "Cxyz";
  std::istringstream in(bytes);
  LcmLogReader r(in);
  LcmLogEvent e;
  CHECK(r.next(e));
  CHECK_FALSE(r.next(e));
  CHECK(r.count(LogProblemKind::truncated) == 1);
  CHECK(e.data.capacity() <= 64u * 1024u);
  REQUIRE(r.problems().size() == 1);
  CHECK(hal::lcm::describe(r.problems()[0]) ==
        "truncated at byte " + std::to_string(bytes.size()) + ", in event 2 (channel C): 32 of " +
            std::to_string(28 + 1 + 64 * 1024 * 1024) + " bytes present");
}
