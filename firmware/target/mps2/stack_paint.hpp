#pragma once
// The stack's high-water mark, measured by painting (board support): stack_paint() fills the free stack below its
// caller's frame with a pattern, down to the end of static data but at most kStackPaintWindow bytes; after the work
// to measure, stack_high_water() is how far below the painted top the deepest word written since lies. The work
// must run from the same caller (its frames start at the painted top). A write that leaves the pattern's value in
// a word is missed: the figure is a lower bound of the true depth by at most that, and the static bound of the
// call graph (tests/board/stack_bound.cpp) is the upper one.
#include <cstdint>

namespace board {

inline constexpr std::uint32_t kStackPaintWindow = 60u * 1024u;  // the linker keeps at least 64 KiB of stack

// Paints below `sp`, the caller's stack pointer (stack_paint() passes it).
void stack_paint_below(std::uintptr_t sp);
__attribute__((always_inline)) inline void stack_paint() {
  std::uintptr_t sp;
  __asm__ volatile("mov %0, sp" : "=r"(sp));
  stack_paint_below(sp);
}
// Bytes below the caller's stack pointer at stack_paint() written since; kStackPaintWindow or more when the whole
// window was used (the true depth may be more).
std::uint32_t stack_high_water();

}  // namespace board
