#pragma once
// A fuzz input as a file without touching the disk: the importers open paths, so each input goes into a memfd and
// the importer is given /proc/self/fd/N. Closed when it goes out of scope.
#include <sys/mman.h>
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <string>

namespace fuzz {

class MemFile {
 public:
  MemFile(const char* name, const std::uint8_t* data, std::size_t size) : fd_(memfd_create(name, 0)) {
    if (fd_ < 0) __builtin_trap();
    if (size > 0 && write(fd_, data, size) != static_cast<ssize_t>(size)) __builtin_trap();
  }
  MemFile(const MemFile&) = delete;
  MemFile& operator=(const MemFile&) = delete;
  ~MemFile() { close(fd_); }
  std::string path() const { return "/proc/self/fd/" + std::to_string(fd_); }

 private:
  int fd_;
};

}  // namespace fuzz
