// Buffered host files over semihosting (semihosting_file.hpp).
#include "semihosting_file.hpp"

namespace board {

bool FileReader::open(const char* path) {
  close();
  const int h = file_open(path, FileMode::read_binary);
  open_handle_ = h >= 0 ? h + 1 : 0;
  begin_ = end_ = 0;
  eof_ = false;
  long_lines_ = 0;
  bytes_ = 0;
  return is_open();
}

void FileReader::close() {
  if (is_open()) file_close(handle());
  open_handle_ = 0;
}

bool FileReader::fill() {
  if (begin_ < end_) return true;
  if (eof_ || !is_open()) return false;
  begin_ = 0;
  end_ = file_read(handle(), block_, kBlock);
  bytes_ += end_;
  if (end_ < kBlock) eof_ = true;  // a short read is the end of the file (or an error: the same for a reader)
  return end_ > 0;
}

bool FileReader::get(char& c) {
  if (!fill()) return false;
  c = block_[begin_++];
  return true;
}

std::size_t FileReader::read(void* out, std::size_t n) {
  char* dst = static_cast<char*>(out);
  std::size_t done = 0;
  while (done < n && fill()) {  // each pass consumes at least one byte
    std::size_t take = end_ - begin_;
    if (take > n - done) take = n - done;
    for (std::size_t i = 0; i < take; ++i) dst[done + i] = block_[begin_ + i];
    begin_ += take;
    done += take;
  }
  return done;
}

bool FileReader::next_line(const char*& line, std::size_t& length) {
  std::size_t n = 0;
  bool any = false, cut = false;
  while (fill()) {  // each pass consumes at least one byte
    any = true;
    const char c = block_[begin_++];
    if (c == '\n') break;
    if (n < kMaxLine)
      line_[n++] = c;
    else
      cut = true;
  }
  if (!any) return false;
  if (cut) ++long_lines_;
  line_[n] = '\0';
  line = line_;
  length = n;
  return true;
}

bool FileWriter::open(const char* path) {
  close();
  const int h = file_open(path, FileMode::write_binary);
  open_handle_ = h >= 0 ? h + 1 : 0;
  used_ = 0;
  failures_ = 0;
  bytes_ = 0;
  return is_open();
}

bool FileWriter::flush() {
  if (used_ == 0) return true;
  const bool ok = is_open() && file_write(handle(), block_, used_);
  if (!ok) ++failures_;
  used_ = 0;
  return ok;
}

bool FileWriter::close() {
  if (!is_open()) return failures_ == 0;
  flush();
  if (!file_close(handle())) ++failures_;
  open_handle_ = 0;
  return failures_ == 0;
}

bool FileWriter::write(const char* data, std::size_t n) {
  if (!is_open()) {
    ++failures_;
    return false;
  }
  const std::uint32_t before = failures_;
  for (std::size_t i = 0; i < n; ++i) {
    if (used_ == kBlock) flush();
    block_[used_++] = data[i];
  }
  bytes_ += n;
  return failures_ == before;
}

}  // namespace board
