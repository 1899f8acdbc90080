// firmware-selftest for the qemu mps2 boards: runs the self-test workload, prints each section's digest and the
// combined one, exits 0 only if every section matches its expected digest.
#include "../../selftest/selftest.hpp"
#include "semihosting.hpp"

#ifndef EST_BOARD_NAME
#error "EST_BOARD_NAME must name the board"
#endif

#ifdef EST_HEAP_GATE_PROBE
int heap_gate_probe();
#endif

int main() {
  static est::selftest::Result results[est::selftest::kMaxSections];
  const int n = est::selftest::run_all(results);
  int failures = 0;
#ifdef EST_HEAP_GATE_PROBE
  failures += heap_gate_probe();
#endif
  for (int i = 0; i < n; ++i) {
    board::write("section ");
    board::write(results[i].name);
    board::write(" ");
    board::write_hex(results[i].digest, 16);
    if (!results[i].ok()) {
      board::write(" MISMATCH expected ");
      board::write_hex(results[i].expected, 16);
      ++failures;
    }
    board::write("\n");
  }
  board::write("firmware-selftest " EST_BOARD_NAME " digest ");
  board::write_hex(est::selftest::combined(results, n), 16);
  board::write(failures == 0 ? " PASS\n" : " FAIL\n");
  return failures == 0 ? 0 : 1;
}
