// libFuzzer target: any bytes read as an LCM log file (hal/lcm/lcm_log_reader.hpp). Every event handed out lies
// inside the file, after the one before, with lengths in the format's bounds; the reader ends; a file with no event
// and no problem is empty.
#include <cstddef>
#include <cstdint>
#include <sstream>
#include <string>

#include "hal/lcm/lcm_log_reader.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  std::istringstream in(std::string(reinterpret_cast<const char*>(data), size));
  hal::lcm::LcmLogReader reader(in);
  hal::lcm::LcmLogEvent e;
  std::uint64_t next_free = 0, events = 0;
  while (reader.next(e)) {
    ++events;
    const std::uint64_t end = e.offset + 28 + e.channel.size() + e.data.size();
    if (e.offset < next_free || end > size || e.channel.empty() ||
        e.channel.size() > static_cast<std::size_t>(hal::lcm::kMaxLogChannelBytes))
      __builtin_trap();
    next_free = end;
  }
  if (reader.events() != events || reader.offset() > size) __builtin_trap();
  if (events == 0 && reader.problems().empty() && size != 0) __builtin_trap();
  for (const hal::lcm::LogProblem& p : reader.problems())
    if (hal::lcm::describe(p).empty()) __builtin_trap();
  if (reader.problems().size() > hal::lcm::LcmLogReader::kMaxKeptProblems) __builtin_trap();
  return 0;
}
