#pragma once
// Instruction counting on qemu's mps2 boards with SysTick, for the bench images (board support, not firmware).
//
// Under `qemu -icount shift=10` every instruction advances virtual time by 2^10 ns and SysTick counts at 25 MHz
// (40 ns), so instructions = ticks * 40 / 1024, exactly and repeatably (PLATFORM-NOTES, "Counting target
// instructions"; never shift=auto). DWT CYCCNT is not emulated on mps2. SysTick is only 24 bits wide, which at
// shift=10 is 655 360 instructions: the counter therefore moves the vector table (VTOR) to a RAM copy whose SysTick
// entry counts wraps, so a measurement can span 2^64 ticks. Each wrap costs the handler's few instructions once
// every 655 360 counted, a bias below 1e-4, stated rather than subtracted. Calibrated by bench-mcl: a loop of
// exactly 2 000 000 instructions (three wraps) counts 2 000 021 to 2 000 030 depending on the build, i.e. ~13 for
// start + read and ~5 per wrap; the image fails if the count is off by more than 100 (as it is without -icount).
// SysTick keeps running (counting wraps) after a measurement; of the vectors, only its entry differs from boot.
#include <cstdint>

namespace board {

// Installs the wrap-counting vector table (once) and restarts the count at zero.
void instruction_counter_start();
// SysTick ticks since instruction_counter_start().
std::uint64_t instruction_counter_ticks();
// Instructions since instruction_counter_start(), valid under -icount shift=10 only.
inline std::uint64_t instruction_counter_read() { return instruction_counter_ticks() * 40u / 1024u; }

}  // namespace board
