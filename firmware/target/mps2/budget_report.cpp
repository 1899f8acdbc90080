#include "budget_report.hpp"

#include "semihosting.hpp"

namespace board {

void report_budget(const char* key, std::uint64_t value, const char* unit) {
  write("budget ");
  write(key);
  write(" ");
  write_dec(value);
  write(" ");
  write(unit);
  write("\n");
}

}  // namespace board
