// Vector table and reset handler for the Cortex-M4F/M7 qemu mps2 boards (AN386, AN500).
#include <cstdint>

#include "semihosting.hpp"

extern "C" {
extern std::uint32_t _sidata[], _sdata[], _edata[], _sbss[], _ebss[], _estack[];
extern void (*__preinit_array_start[])();
extern void (*__preinit_array_end[])();
extern void (*__init_array_start[])();
extern void (*__init_array_end[])();
int main();
void Reset_Handler();
void Fault_Handler();
}

namespace {
constexpr std::uintptr_t kCpacr = 0xE000ED88u;  // Coprocessor Access Control Register
}

// A fault ends the run with a distinct exit code instead of hanging qemu.
extern "C" void Fault_Handler() {
  board::write("fault: the firmware took an exception\n");
  board::exit(3);
}

extern "C" void Reset_Handler() {
  // CP10 and CP11 full access: the FPU must be on before the first float instruction.
  *reinterpret_cast<volatile std::uint32_t*>(kCpacr) |= (0xFu << 20);
  __asm__ volatile("dsb\n isb" ::: "memory");

  for (std::uint32_t *src = _sidata, *dst = _sdata; dst < _edata;) *dst++ = *src++;
  for (std::uint32_t* dst = _sbss; dst < _ebss;) *dst++ = 0u;
  for (auto f = __preinit_array_start; f < __preinit_array_end; ++f) (*f)();
  for (auto f = __init_array_start; f < __init_array_end; ++f) (*f)();

  board::exit(main());
}

// Cortex-M exception vectors 0-15; the mps2 peripherals' interrupts are not used.
__attribute__((section(".isr_vector"), used)) void (*const g_vectors[16])() = {
    reinterpret_cast<void (*)()>(_estack),
    Reset_Handler,
    Fault_Handler,  // NMI
    Fault_Handler,  // HardFault
    Fault_Handler,  // MemManage
    Fault_Handler,  // BusFault
    Fault_Handler,  // UsageFault
    nullptr, nullptr, nullptr, nullptr,
    Fault_Handler,  // SVCall
    Fault_Handler,  // DebugMonitor
    nullptr,
    Fault_Handler,  // PendSV
    Fault_Handler,  // SysTick
};
