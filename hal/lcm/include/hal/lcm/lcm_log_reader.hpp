#pragma once
// Reading LCM log files (the lcm-logger / lcm_eventlog format) with every fault said and counted (host only). Each
// event: sync word 0xEDA1DA01, event number (int64), timestamp (int64, us), channel length (int32), data length
// (int32), the channel, the data, all big-endian. liblcm's reader skips any bytes up to a sync word and stops
// silently at a cut, so a file of random bytes read as an empty log and a truncated one as a shorter log; this one
// refuses a file whose first event has no sync word, and reports a cut event, a bad sync word between events and an
// impossible length with the byte offset, the event's ordinal and (when read) its channel.
#include <array>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <istream>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

namespace hal::lcm {

inline constexpr std::uint32_t kLogSyncWord = 0xEDA1DA01u;
inline constexpr std::int32_t kMaxLogChannelBytes = 256;          // LCM itself allows 63
inline constexpr std::int32_t kMaxLogDataBytes = 64 * 1024 * 1024;  // far above any est_lcm message

struct LcmLogEvent {
  std::uint64_t offset = 0;  // byte offset of the event's sync word
  std::int64_t event_number = 0;  // as written
  std::int64_t timestamp_us = 0;
  std::string channel;
  std::vector<std::uint8_t> data;
  int size() const { return static_cast<int>(data.size()); }
};

enum class LogProblemKind : std::uint8_t {
  not_a_log,  // the first event has no sync word: the reader stops
  bad_sync,   // no sync word where the next event should start: bytes skipped to the next sync word
  oversize,   // a channel or data length outside the format's bounds: the header is skipped
  truncated,  // the file ends inside an event: the reader stops
  read_error, // the stream failed before its end
  kCount
};
const char* to_string(LogProblemKind k);

struct LogProblem {
  LogProblemKind kind = LogProblemKind::not_a_log;
  std::uint64_t offset = 0;   // where it was found
  std::uint64_t event = 0;    // ordinal (from 1) of the event being read
  std::string channel;        // when the header was read
  std::int64_t length = 0;    // oversize: the length read; truncated: bytes the event needed
  std::uint64_t present = 0;  // truncated: bytes of the event present; bad_sync: bytes skipped
};
// "truncated at byte 5120, in event 17 (channel EST_RANGE_SCAN): 1104 of 1544 bytes present"
std::string describe(const LogProblem& p);

class LcmLogReader {
 public:
  explicit LcmLogReader(std::istream& in) : in_(&in) {}
  // Opens a file; !good() when it cannot be opened (problems() then says nothing: the caller names the file).
  explicit LcmLogReader(const std::string& path);

  bool good() const { return in_ != nullptr && open_; }
  // The next event; false at the end of the file, clean or not.
  bool next(LcmLogEvent& out);

  std::uint64_t events() const { return events_; }
  std::uint64_t offset() const { return offset_; }
  // The file is not an LCM log (nothing was read from it, whatever the reason).
  bool refused() const { return events_ == 0 && !problems_.empty(); }
  std::uint64_t count(LogProblemKind k) const { return counts_[static_cast<std::size_t>(k)]; }
  std::uint64_t problems_total() const;
  // The first kMaxKeptProblems problems, in file order.
  static constexpr std::size_t kMaxKeptProblems = 32;
  const std::vector<LogProblem>& problems() const { return problems_; }

  // "PATH: <problem>" for each kept problem, then "PATH: N more problems" when some were not kept; each line starts
  // with `prefix` (the program's name).
  void print_problems(std::FILE* f, const char* prefix, const std::string& path) const;

 private:
  bool read(void* dst, std::size_t n, std::size_t& got);
  bool resync();  // to the next sync word after offset_; false at the end
  void problem(LogProblem p);

  std::unique_ptr<std::ifstream> file_;
  std::istream* in_ = nullptr;
  bool open_ = true;
  bool done_ = false;
  std::uint64_t offset_ = 0;
  std::uint64_t events_ = 0;
  std::array<std::uint64_t, static_cast<std::size_t>(LogProblemKind::kCount)> counts_{};
  std::vector<LogProblem> problems_;
};

// For host tools: every event of the log at `path` handed to `on_event`, then the problems printed on `warnings`
// (when given) with the tool's name. Throws std::runtime_error naming the file and the reason when it cannot be
// opened or holds no event. Returns the number of problems (a truncated or damaged log still gives its events).
std::runtime_error log_refusal(const LcmLogReader& reader, const std::string& path);

template <typename OnEvent>
std::uint64_t read_lcm_log(const std::string& path, const char* tool, std::FILE* warnings, OnEvent&& on_event) {
  LcmLogReader reader(path);
  if (!reader.good()) throw log_refusal(reader, path);
  LcmLogEvent e;
  while (reader.next(e)) on_event(static_cast<const LcmLogEvent&>(e));
  if (reader.events() == 0) throw log_refusal(reader, path);
  if (warnings != nullptr) reader.print_problems(warnings, tool, path);
  return reader.problems_total();
}

}  // namespace hal::lcm
