// Linked only into heap-gate-probe, which must NOT link: one reachable std::vector is enough to trip the gate.
#include <vector>

int heap_gate_probe() {
  std::vector<int> v(3);
  return static_cast<int>(v.size()) - 3;
}
