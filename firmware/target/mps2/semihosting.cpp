#include "semihosting.hpp"

namespace board {
namespace {

constexpr int kSysWrite0 = 0x04;
constexpr int kSysExitExtended = 0x20;
constexpr std::uint32_t kAdpStoppedApplicationExit = 0x20026u;

int semihost(int op, const void* arg) {
  register int r0 __asm__("r0") = op;
  register const void* r1 __asm__("r1") = arg;
  __asm__ volatile("bkpt 0xAB" : "+r"(r0) : "r"(r1) : "memory");
  return r0;
}

}  // namespace

void write(const char* text) { semihost(kSysWrite0, text); }

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
