// LCM log files read with their faults said (hal/lcm/lcm_log_reader.hpp).
#include "hal/lcm/lcm_log_reader.hpp"

#include <algorithm>

namespace hal::lcm {

namespace {

constexpr std::size_t kHeaderBytes = 4 + 8 + 8 + 4 + 4;

std::uint64_t big_endian(const unsigned char* p, int bytes) {
  std::uint64_t v = 0;
  for (int i = 0; i < bytes; ++i) v = (v << 8) | p[i];
  return v;
}

}  // namespace

const char* to_string(LogProblemKind k) {
  switch (k) {
    case LogProblemKind::not_a_log: return "not_a_log";
    case LogProblemKind::bad_sync: return "bad_sync";
    case LogProblemKind::oversize: return "oversize";
    case LogProblemKind::truncated: return "truncated";
    case LogProblemKind::read_error: return "read_error";
    default: return "?";
  }
}

std::string describe(const LogProblem& p) {
  const std::string at = std::to_string(p.offset);
  const std::string in_event =
      "in event " + std::to_string(p.event) + (p.channel.empty() ? std::string() : " (channel " + p.channel + ")");
  switch (p.kind) {
    case LogProblemKind::not_a_log:
      return "not an LCM log: no sync word (0xEDA1DA01) at byte " + at + ", where its first event should start";
    case LogProblemKind::bad_sync:
      return "bad sync word at byte " + at + ", where event " + std::to_string(p.event) + " should start: " +
             std::to_string(p.present) + " bytes skipped to the next sync word";
    case LogProblemKind::oversize:
      return "impossible length " + std::to_string(p.length) + " at byte " + at + ", " + in_event +
             " (channel 1.." + std::to_string(kMaxLogChannelBytes) + ", data 0.." + std::to_string(kMaxLogDataBytes) +
             " bytes): event skipped";
    case LogProblemKind::truncated:
      return "truncated at byte " + at + ", " + in_event + ": " + std::to_string(p.present) + " of " +
             std::to_string(p.length) + " bytes present";
    case LogProblemKind::read_error: return "read error at byte " + at + ", " + in_event;
    default: return "?";
  }
}

LcmLogReader::LcmLogReader(const std::string& path)
    : file_(std::make_unique<std::ifstream>(path, std::ios::binary)), in_(file_.get()), open_(file_->is_open()) {}

std::uint64_t LcmLogReader::problems_total() const {
  std::uint64_t n = 0;
  for (std::uint64_t c : counts_) n += c;
  return n;
}

void LcmLogReader::problem(LogProblem p) {
  ++counts_[static_cast<std::size_t>(p.kind)];
  if (problems_.size() < kMaxKeptProblems) problems_.push_back(std::move(p));
}

bool LcmLogReader::read(void* dst, std::size_t n, std::size_t& got) {
  in_->read(static_cast<char*>(dst), static_cast<std::streamsize>(n));
  got = static_cast<std::size_t>(in_->gcount());
  offset_ += got;
  return got == n;
}

bool LcmLogReader::resync() {
  in_->clear();
  if (!in_->seekg(static_cast<std::streamoff>(offset_))) return false;
  std::uint32_t window = 0;
  int have = 0;
  for (int c = in_->get(); c != std::char_traits<char>::eof(); c = in_->get()) {
    window = (window << 8) | static_cast<std::uint32_t>(c);
    ++offset_;
    if (++have >= 4 && window == kLogSyncWord) {
      offset_ -= 4;
      in_->clear();
      return static_cast<bool>(in_->seekg(static_cast<std::streamoff>(offset_)));
    }
  }
  return false;
}

bool LcmLogReader::next(LcmLogEvent& out) {
  // Each pass reads one event or passes over one damaged stretch, so the loop ends with the file.
  while (!done_ && good()) {
    const std::uint64_t start = offset_;
    const std::uint64_t ordinal = events_ + 1;
    LogProblem p;
    p.offset = start;
    p.event = ordinal;
    unsigned char h[kHeaderBytes];
    std::size_t got = 0;
    const bool whole_header = read(h, kHeaderBytes, got);
    if (got == 0 && !in_->bad()) {  // the clean end
      done_ = true;
      break;
    }
    const bool synced = got >= 4 && static_cast<std::uint32_t>(big_endian(h, 4)) == kLogSyncWord;
    if (!synced && events_ == 0 && start == 0) {
      p.kind = LogProblemKind::not_a_log;
      problem(std::move(p));
      done_ = true;
      break;
    }
    if (!synced && got >= 4) {
      offset_ = start + 1;
      const bool found = resync();
      p.kind = LogProblemKind::bad_sync;
      p.present = offset_ - start;
      problem(std::move(p));
      if (!found) done_ = true;
      continue;
    }
    if (!whole_header) {
      p.kind = in_->bad() ? LogProblemKind::read_error : LogProblemKind::truncated;
      p.offset = offset_;
      p.length = static_cast<std::int64_t>(kHeaderBytes);
      p.present = got;
      problem(std::move(p));
      done_ = true;
      break;
    }
    const auto channel_bytes = static_cast<std::int32_t>(static_cast<std::uint32_t>(big_endian(h + 20, 4)));
    const auto data_bytes = static_cast<std::int32_t>(static_cast<std::uint32_t>(big_endian(h + 24, 4)));
    if (channel_bytes <= 0 || channel_bytes > kMaxLogChannelBytes || data_bytes < 0 || data_bytes > kMaxLogDataBytes) {
      p.kind = LogProblemKind::oversize;
      p.length = channel_bytes <= 0 || channel_bytes > kMaxLogChannelBytes ? channel_bytes : data_bytes;
      problem(std::move(p));
      offset_ = start + 1;
      if (!resync()) done_ = true;
      continue;
    }
    const std::size_t need = kHeaderBytes + static_cast<std::size_t>(channel_bytes) + static_cast<std::size_t>(data_bytes);
    out.channel.resize(static_cast<std::size_t>(channel_bytes));
    std::size_t got_channel = 0, got_data = 0;
    const bool whole_channel = read(out.channel.data(), out.channel.size(), got_channel);
    // Grown as the bytes arrive: a header claiming 64 MB in a short file allocates what the file holds.
    out.data.clear();
    bool whole = whole_channel;
    while (whole && got_data < static_cast<std::size_t>(data_bytes)) {
      const std::size_t chunk = std::min<std::size_t>(64 * 1024, static_cast<std::size_t>(data_bytes) - got_data);
      out.data.resize(got_data + chunk);
      std::size_t got_chunk = 0;
      whole = read(out.data.data() + got_data, chunk, got_chunk);
      got_data += got_chunk;
    }
    if (!whole) {
      p.kind = in_->bad() ? LogProblemKind::read_error : LogProblemKind::truncated;
      p.offset = offset_;
      if (whole_channel) p.channel = out.channel;
      p.length = static_cast<std::int64_t>(need);
      p.present = kHeaderBytes + got_channel + got_data;
      problem(std::move(p));
      done_ = true;
      break;
    }
    out.offset = start;
    out.event_number = static_cast<std::int64_t>(big_endian(h + 4, 8));
    out.timestamp_us = static_cast<std::int64_t>(big_endian(h + 12, 8));
    ++events_;
    return true;
  }
  return false;
}

void LcmLogReader::print_problems(std::FILE* f, const char* prefix, const std::string& path) const {
  for (const LogProblem& p : problems_) std::fprintf(f, "%s: %s: %s\n", prefix, path.c_str(), describe(p).c_str());
  const std::uint64_t total = problems_total();
  if (total > problems_.size())
    std::fprintf(f, "%s: %s: %llu more problems\n", prefix, path.c_str(),
                 static_cast<unsigned long long>(total - problems_.size()));
}

std::runtime_error log_refusal(const LcmLogReader& reader, const std::string& path) {
  if (!reader.good()) return std::runtime_error(path + ": cannot open");
  if (!reader.problems().empty()) return std::runtime_error(path + ": " + describe(reader.problems().front()));
  return std::runtime_error(path + ": no LCM event in it (an empty file)");
}

}  // namespace hal::lcm
