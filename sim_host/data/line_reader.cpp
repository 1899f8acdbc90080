#include "data/line_reader.hpp"

#include "data/import_report.hpp"

#include <zlib.h>

#include <charconv>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <stdexcept>

namespace sim::data {

LineReader::LineReader(const std::string& path) : file_(gzopen(path.c_str(), "rb")), path_(path), buffer_(1 << 16) {
  if (file_ == nullptr) throw std::runtime_error(path + ": cannot open");
}

LineReader::~LineReader() { gzclose(static_cast<gzFile>(file_)); }

bool LineReader::next(std::string& line) {
  line.clear();
  gzFile f = static_cast<gzFile>(file_);
  bool any = false;
  for (;;) {
    if (begin_ == end_) {
      if (eof_) break;
      const int n = gzread(f, buffer_.data(), static_cast<unsigned>(buffer_.size()));
      int err = Z_OK;
      const char* msg = gzerror(f, &err);
      // A cut gzip stream reads up to the cut, then says so (Z_BUF_ERROR).
      if (n < 0 || (n == 0 && err != Z_OK && err != Z_STREAM_END))
        throw std::runtime_error(path_ + ": read error: " + msg);
      begin_ = 0;
      end_ = static_cast<std::size_t>(n);
      if (n == 0) {
        eof_ = true;
        break;
      }
    }
    any = true;
    const char* b = buffer_.data() + begin_;
    const void* nl = std::memchr(b, '\n', end_ - begin_);
    const std::size_t take = nl != nullptr ? static_cast<std::size_t>(static_cast<const char*>(nl) - b) : end_ - begin_;
    line.append(b, take);
    begin_ += take;
    if (nl != nullptr) {
      ++begin_;  // the LF
      break;
    }
  }
  if (!any) return false;
  while (!line.empty() && line.back() == '\r') line.pop_back();
  ++line_;
  return true;
}

NumericRows read_numeric_rows(const std::string& path, std::size_t fields, ImportReport& report, char comment,
                              bool monotonic_time) {
  NumericRows r;
  r.path = path;
  LineReader in(path);
  std::string line;
  double last_t = -std::numeric_limits<double>::infinity();
  while (in.next(line)) {
    if (blank_or_comment(line, comment)) continue;
    const auto f = split_fields(line);
    if (f.size() != fields) {
      report.bad_line(path, in.line_number(), std::to_string(fields) + " fields expected");
      continue;
    }
    std::vector<double> v(fields);
    bool ok = true;
    for (std::size_t i = 0; i < fields && ok; ++i) ok = parse_double(f[i], v[i]);
    if (!ok) {
      report.bad_line(path, in.line_number(), "a field is not a finite number");
      continue;
    }
    if (monotonic_time && v[0] < last_t) {
      report.bad_line(path, in.line_number(), "time before the previous row's");
      continue;
    }
    last_t = v[0];
    r.values.push_back(std::move(v));
    r.lines.push_back(in.line_number());
  }
  return r;
}

std::vector<std::string_view> split_fields(std::string_view line) {
  std::vector<std::string_view> out;
  std::size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && (line[i] == ' ' || line[i] == '\t' || line[i] == '\r')) ++i;
    std::size_t j = i;
    while (j < line.size() && line[j] != ' ' && line[j] != '\t' && line[j] != '\r') ++j;
    if (j > i) out.push_back(line.substr(i, j - i));
    i = j;
  }
  return out;
}

bool blank_or_comment(std::string_view line, char comment) {
  for (char c : line) {
    if (c == ' ' || c == '\t' || c == '\r') continue;
    return c == comment;
  }
  return true;
}

bool parse_double(std::string_view field, double& out) {
  if (field.empty()) return false;
  // strtod on a bounded copy: std::from_chars for double is not in every libstdc++ this project builds with.
  char buf[64];
  if (field.size() >= sizeof buf) return false;
  field.copy(buf, field.size());
  buf[field.size()] = '\0';
  char* end = nullptr;
  const double v = std::strtod(buf, &end);
  if (end != buf + field.size() || !std::isfinite(v)) return false;
  out = v;
  return true;
}

bool parse_int(std::string_view field, std::int64_t& out) {
  if (field.empty()) return false;
  const char* b = field.data();
  const char* e = b + field.size();
  if (*b == '+') ++b;
  const auto r = std::from_chars(b, e, out);
  return r.ec == std::errc() && r.ptr == e;
}

}  // namespace sim::data
