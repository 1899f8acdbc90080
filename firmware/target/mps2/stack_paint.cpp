#include "stack_paint.hpp"

extern "C" std::uint32_t _ebss[];

namespace board {
namespace {

constexpr std::uint32_t kPaint = 0xC5ACCE55u;
constexpr std::uintptr_t kFrameMargin = 128u;  // stack_paint_below's own frame, above the painted top
std::uint32_t* g_top = nullptr;                // one past the highest painted word
std::uint32_t* g_bottom = nullptr;             // the lowest painted word

}  // namespace

void stack_paint_below(std::uintptr_t sp) {
  const std::uintptr_t top = (sp - kFrameMargin) & ~std::uintptr_t{3};
  std::uintptr_t bottom = top - kStackPaintWindow;
  const std::uintptr_t data_end = reinterpret_cast<std::uintptr_t>(_ebss);
  if (bottom < data_end) bottom = data_end;
  g_top = reinterpret_cast<std::uint32_t*>(top);
  g_bottom = reinterpret_cast<std::uint32_t*>(bottom);
  for (volatile std::uint32_t* p = g_bottom; p < g_top; ++p) *p = kPaint;
}

std::uint32_t stack_high_water() {
  const volatile std::uint32_t* p = g_bottom;
  while (p < g_top && *p == kPaint) ++p;
  // The painted top is kFrameMargin below the caller's stack pointer at stack_paint(): count from there (the
  // margin counts as used: a step whose stack is within it is not told apart from one that used none).
  return static_cast<std::uint32_t>(reinterpret_cast<std::uintptr_t>(g_top) - reinterpret_cast<std::uintptr_t>(p)) +
         static_cast<std::uint32_t>(kFrameMargin);
}

}  // namespace board
