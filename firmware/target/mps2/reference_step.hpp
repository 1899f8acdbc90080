#pragma once
// What the reference images share (board support): each runs one reference configuration's loop on a fixed
// workload, counts the instructions of every step (instruction_counter.hpp, exact under -icount shift=10), paints
// the stack around the steps (stack_paint.hpp) and reports the figures as budget lines (budget_report.hpp).
//
// A step is one call of reference_step(), which the image points at its loop's run(); it is a function of its own,
// never inlined, so that tests/board/stack_bound.cpp can bound its stack from the compiler's call graph
// (-fcallgraph-info) by the same name the image's painted figure is measured under.
#include <cstdint>

#include "budget_report.hpp"
#include "instruction_counter.hpp"
#include "semihosting.hpp"

extern "C" void reference_step();

namespace board {

// The instructions of steps: how many, their mean and the largest.
struct StepCounts {
  std::uint64_t steps = 0, total = 0, largest = 0;
  void add(std::uint64_t n) {
    ++steps;
    total += n;
    largest = n > largest ? n : largest;
  }
  std::uint64_t mean() const { return steps > 0u ? total / steps : 0u; }
};

// One reference_step(), counted.
inline std::uint64_t counted_step() {
  instruction_counter_start();
  reference_step();
  return instruction_counter_read();
}

// "<image>: <what>: <steps> steps, mean <m>, largest <l> instructions"
inline void write_counts(const char* image, const char* what, const StepCounts& c) {
  write(image);
  write(": ");
  write(what);
  write(": ");
  write_dec(c.steps);
  write(" steps, mean ");
  write_dec(c.mean());
  write(", largest ");
  write_dec(c.largest);
  write(" instructions\n");
}

}  // namespace board
