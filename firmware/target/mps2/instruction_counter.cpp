// SysTick-based instruction counter with a wrap count kept by the SysTick exception (see the header).
#include "instruction_counter.hpp"

extern "C" void est_instruction_counter_systick();

namespace board {
namespace {

constexpr std::uintptr_t kVtor = 0xE000ED08u;
constexpr std::uintptr_t kSystCsr = 0xE000E010u;
constexpr std::uintptr_t kSystRvr = 0xE000E014u;
constexpr std::uintptr_t kSystCvr = 0xE000E018u;
constexpr std::uint32_t kReload = 0x00FFFFFFu;  // period 2^24 ticks

volatile std::uint32_t& reg(std::uintptr_t a) { return *reinterpret_cast<volatile std::uint32_t*>(a); }

// VTOR needs the table aligned to its size rounded up to a power of two; 16 core entries + room for the mps2
// interrupts: 1 KiB covers every case.
alignas(1024) void (*g_ram_vectors[256])();
volatile std::uint32_t g_wraps = 0;
bool g_installed = false;

}  // namespace

void instruction_counter_start() {
  if (!g_installed) {
    // The RAM copy starts from the table in use (startup.cpp's, at VTOR = 0 after reset).
    using Vector = void (*)();
    const Vector* boot = reinterpret_cast<const Vector*>(static_cast<std::uintptr_t>(reg(kVtor)));
    for (int i = 0; i < 16; ++i) g_ram_vectors[i] = boot[i];
    g_ram_vectors[15] = est_instruction_counter_systick;
    __asm__ volatile("dsb" ::: "memory");
    reg(kVtor) = static_cast<std::uint32_t>(reinterpret_cast<std::uintptr_t>(&g_ram_vectors[0]));
    __asm__ volatile("dsb\n isb" ::: "memory");
    g_installed = true;
  }
  reg(kSystCsr) = 0u;
  reg(kSystRvr) = kReload;
  g_wraps = 0u;
  reg(kSystCvr) = 0u;    // any write clears the counter and COUNTFLAG
  reg(kSystCsr) = 0x7u;  // ENABLE | TICKINT | CLKSOURCE (processor clock)
}

std::uint64_t instruction_counter_ticks() {
  // The down-counter and the wrap count are read twice around each other so a wrap between the reads is seen.
  for (int attempt = 0; attempt < 4; ++attempt) {
    const std::uint32_t w0 = g_wraps;
    const std::uint32_t v = reg(kSystCvr) & kReload;
    const std::uint32_t w1 = g_wraps;
    if (w0 == w1) {
      // Right after the reload the counter reads kReload: elapsed in this period is kReload - v (0 .. 2^24 - 1).
      return static_cast<std::uint64_t>(w0) * (static_cast<std::uint64_t>(kReload) + 1u) + (kReload - v);
    }
  }
  return static_cast<std::uint64_t>(g_wraps) * (static_cast<std::uint64_t>(kReload) + 1u);
}

}  // namespace board

extern "C" void est_instruction_counter_systick() { board::g_wraps = board::g_wraps + 1u; }
