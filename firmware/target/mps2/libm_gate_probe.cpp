// Linked only into libm-gate-probe: one sinf made reachable (through a volatile, from a constructor that the linker
// script keeps) must be caught by check_no_libm.cmake.
#include <cmath>

namespace {
volatile float g_probe_in = 0.5f;
volatile float g_probe_out = 0.0f;
__attribute__((constructor)) void libm_gate_probe() { g_probe_out = std::sin(g_probe_in); }
}  // namespace
