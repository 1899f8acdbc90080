#pragma once
// ARM semihosting (ARM DUI 0471, "Semihosting operations") for qemu's mps2 boards: output goes to qemu's stderr and
// the exit code becomes qemu's exit status. Board support only; the firmware proper never does I/O.
//
// Host files (qemu -semihosting-config enable=on,target=native): paths are the host's, relative to qemu's working
// directory. The command line is what qemu was given as `-semihosting-config ...,arg=A,arg=B` (or, without arg=,
// the kernel's file name), the arguments joined with single spaces.
#include <cstddef>
#include <cstdint>

namespace board {

void write(const char* text);                 // SYS_WRITE0
void write_hex(std::uint64_t value, int digits);
void write_dec(std::uint64_t value);
[[noreturn]] void exit(int code);             // SYS_EXIT_EXTENDED

enum class FileMode : std::uint8_t { read_binary, write_binary };
// SYS_OPEN: a handle >= 0, or -1.
int file_open(const char* path, FileMode mode);
// SYS_CLOSE: false on failure.
bool file_close(int handle);
// SYS_READ: the bytes read into buf (at most n); fewer than n only at the end of the file or on an error.
std::size_t file_read(int handle, void* buf, std::size_t n);
// SYS_WRITE: true when all n bytes were written.
bool file_write(int handle, const void* buf, std::size_t n);
// SYS_FLEN: the file's length in bytes, or -1.
std::int32_t file_length(int handle);
// SYS_GET_CMDLINE into buf (NUL-terminated); false when there is none or it does not fit in `size` bytes.
bool command_line(char* buf, std::size_t size);

}  // namespace board
