#pragma once
// Text files of the datasets, line by line with their numbers, gzipped or not (zlib reads both), and strict number
// fields: a field is a number only when all of it is one and it is finite. Host only.
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace sim::data {

class LineReader {
 public:
  explicit LineReader(const std::string& path);  // throws std::runtime_error when the file cannot be opened
  ~LineReader();
  LineReader(const LineReader&) = delete;
  LineReader& operator=(const LineReader&) = delete;

  // The next line without its end (LF or CRLF), every byte of it (a NUL byte too, which a field's parse then
  // refuses); false at the end of the file. A read error throws.
  bool next(std::string& line);
  std::uint64_t line_number() const { return line_; }
  const std::string& path() const { return path_; }

 private:
  void* file_;  // gzFile
  std::string path_;
  std::uint64_t line_ = 0;
  std::vector<char> buffer_;
  std::size_t begin_ = 0, end_ = 0;  // the bytes of buffer_ read and not yet handed out
  bool eof_ = false;
};

// Whitespace-separated fields (spaces and tabs).
std::vector<std::string_view> split_fields(std::string_view line);
// Whether the line holds only whitespace, or is a comment starting with `comment` after leading whitespace.
bool blank_or_comment(std::string_view line, char comment = '#');

// The numeric rows of a text file of `fields` columns, each with its line number: blank and comment lines passed
// over; a line of another field count, or with a field that is not a finite number, or (with monotonic_time) whose
// first field is before the previous row's, goes to the report (skipped and counted, or refused).
struct NumericRows {
  std::string path;
  std::vector<std::vector<double>> values;
  std::vector<std::uint64_t> lines;
};
class ImportReport;
NumericRows read_numeric_rows(const std::string& path, std::size_t fields, ImportReport& report, char comment = '#',
                              bool monotonic_time = false);

bool parse_double(std::string_view field, double& out);      // finite numbers only
bool parse_int(std::string_view field, std::int64_t& out);  // decimal integers only

}  // namespace sim::data
