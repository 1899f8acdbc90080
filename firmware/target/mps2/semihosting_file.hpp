#pragma once
// Buffered host files over semihosting (semihosting.hpp), for the board images that replay recorded data: a reader
// by lines or bytes and a writer, each with one fixed block of storage and every failure counted. Every loop is
// bounded by the bytes it consumes or produces.
#include <cstddef>
#include <cstdint>

#include "semihosting.hpp"

namespace board {

class FileReader {
 public:
  static constexpr std::size_t kBlock = 4096;
  static constexpr std::size_t kMaxLine = 255;

  FileReader() = default;
  ~FileReader() { close(); }
  FileReader(const FileReader&) = delete;
  FileReader& operator=(const FileReader&) = delete;

  bool open(const char* path);
  void close();
  bool is_open() const { return open_handle_ != 0; }

  // The next line without its '\n' (a '\r' before it is kept), valid until the next call; false at the end of the
  // file. A final line without '\n' is a line, an empty final segment is not (as std::getline). A line longer than
  // kMaxLine is returned cut to kMaxLine bytes and counted in long_lines().
  bool next_line(const char*& line, std::size_t& length);
  // One byte; false at the end of the file.
  bool get(char& c);
  // Up to n bytes; fewer only at the end of the file.
  std::size_t read(void* out, std::size_t n);

  std::uint32_t long_lines() const { return long_lines_; }
  std::uint64_t bytes_read() const { return bytes_; }

 private:
  bool fill();

  int handle() const { return open_handle_ - 1; }
  // The handle + 1 (0: closed), so that a reader is all zeros until opened: .bss, not 4 KiB of .data.
  int open_handle_ = 0;
  char block_[kBlock] = {};
  std::size_t begin_ = 0, end_ = 0;
  bool eof_ = false;
  char line_[kMaxLine + 1] = {};
  std::uint32_t long_lines_ = 0;
  std::uint64_t bytes_ = 0;
};

class FileWriter {
 public:
  static constexpr std::size_t kBlock = 4096;

  FileWriter() = default;
  ~FileWriter() { close(); }
  FileWriter(const FileWriter&) = delete;
  FileWriter& operator=(const FileWriter&) = delete;

  bool open(const char* path);
  // Flushes and closes; false if anything written since open() was lost.
  bool close();
  bool is_open() const { return open_handle_ != 0; }

  // False (and counted) when the bytes could not be written.
  bool write(const char* data, std::size_t n);

  std::uint32_t failures() const { return failures_; }
  std::uint64_t bytes_written() const { return bytes_; }

 private:
  bool flush();

  int handle() const { return open_handle_ - 1; }
  int open_handle_ = 0;  // as FileReader's
  char block_[kBlock] = {};
  std::size_t used_ = 0;
  std::uint32_t failures_ = 0;
  std::uint64_t bytes_ = 0;
};

}  // namespace board
