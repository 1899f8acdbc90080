#pragma once
// Figures the build checks against stored budgets (board support, not firmware): one line per figure on qemu's
// stderr, "budget KEY VALUE UNIT", which check_budgets.cmake compares with budgets/<board>.txt (more than 5 % over
// a budget fails; a figure without a budget fails too). The images print their human-readable lines beside these.
#include <cstdint>

namespace board {

void report_budget(const char* key, std::uint64_t value, const char* unit);

}  // namespace board
