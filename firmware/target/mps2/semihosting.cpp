#include "semihosting.hpp"

namespace board {
namespace {

constexpr int kSysOpen = 0x01;
constexpr int kSysClose = 0x02;
constexpr int kSysWrite0 = 0x04;
constexpr int kSysWrite = 0x05;
constexpr int kSysRead = 0x06;
constexpr int kSysFlen = 0x0C;
constexpr int kSysGetCmdline = 0x15;
constexpr int kSysExitExtended = 0x20;
// SYS_OPEN modes are indices into fopen's "r", "rb", "r+", "r+b", "w", "wb", ...
constexpr std::uint32_t kOpenReadBinary = 1u;
constexpr std::uint32_t kOpenWriteBinary = 5u;
constexpr std::uint32_t kAdpStoppedApplicationExit = 0x20026u;

int semihost(int op, const void* arg) {
  register int r0 __asm__("r0") = op;
  register const void* r1 __asm__("r1") = arg;
  __asm__ volatile("bkpt 0xAB" : "+r"(r0) : "r"(r1) : "memory");
  return r0;
}

std::uint32_t word(const void* p) { return static_cast<std::uint32_t>(reinterpret_cast<std::uintptr_t>(p)); }

std::size_t length_of(const char* s) {
  std::size_t n = 0;
  while (s[n] != '\0') ++n;
  return n;
}

}  // namespace

void write(const char* text) { semihost(kSysWrite0, text); }

int file_open(const char* path, FileMode mode) {
  const std::uint32_t block[3] = {word(path), mode == FileMode::read_binary ? kOpenReadBinary : kOpenWriteBinary,
                                  static_cast<std::uint32_t>(length_of(path))};
  return semihost(kSysOpen, block);
}

bool file_close(int handle) {
  const std::uint32_t block[1] = {static_cast<std::uint32_t>(handle)};
  return semihost(kSysClose, block) == 0;
}

std::size_t file_read(int handle, void* buf, std::size_t n) {
  const std::uint32_t block[3] = {static_cast<std::uint32_t>(handle), word(buf), static_cast<std::uint32_t>(n)};
  const int not_read = semihost(kSysRead, block);  // the bytes NOT read: n at the end of the file
  if (not_read < 0 || static_cast<std::size_t>(not_read) > n) return 0;
  return n - static_cast<std::size_t>(not_read);
}

bool file_write(int handle, const void* buf, std::size_t n) {
  const std::uint32_t block[3] = {static_cast<std::uint32_t>(handle), word(buf), static_cast<std::uint32_t>(n)};
  return semihost(kSysWrite, block) == 0;  // the bytes NOT written
}

std::int32_t file_length(int handle) {
  const std::uint32_t block[1] = {static_cast<std::uint32_t>(handle)};
  return semihost(kSysFlen, block);
}

bool command_line(char* buf, std::size_t size) {
  if (size == 0) return false;
  std::uint32_t block[2] = {word(buf), static_cast<std::uint32_t>(size)};
  if (semihost(kSysGetCmdline, block) != 0) return false;  // block[1]: the length without the NUL
  if (block[1] >= size) return false;
  buf[block[1]] = '\0';
  return true;
}

void write_hex(std::uint64_t value, int digits) {
  char buf[19] = {'0', 'x'};
  for (int i = 0; i < digits && i < 16; ++i) {
    const unsigned nibble = static_cast<unsigned>(value >> (4 * (digits - 1 - i))) & 0xfu;
    buf[2 + i] = static_cast<char>(nibble < 10 ? '0' + nibble : 'a' + nibble - 10);
  }
  buf[2 + (digits < 16 ? digits : 16)] = '\0';
  write(buf);
}

void write_dec(std::uint64_t value) {
  char buf[21];
  int i = 20;
  buf[i] = '\0';
  do {
    buf[--i] = static_cast<char>('0' + value % 10u);
    value /= 10u;
  } while (value != 0u && i > 0);
  write(&buf[i]);
}

void exit(int code) {
  const std::uint32_t block[2] = {kAdpStoppedApplicationExit, static_cast<std::uint32_t>(code)};
  semihost(kSysExitExtended, block);
  for (;;) {
  }
}

}  // namespace board
