#pragma once
// ARM semihosting (ARM DUI 0471, "Semihosting operations") for qemu's mps2 boards: output goes to qemu's stderr and
// the exit code becomes qemu's exit status. Board support only; the firmware proper never does I/O.
#include <cstdint>

namespace board {

void write(const char* text);                 // SYS_WRITE0
void write_hex(std::uint64_t value, int digits);
void write_dec(std::uint64_t value);
[[noreturn]] void exit(int code);             // SYS_EXIT_EXTENDED

}  // namespace board
