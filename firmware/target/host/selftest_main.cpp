// firmware-selftest on the host: the same workload as the boards, printed the same way.
#include <cinttypes>
#include <cstdio>

#include "../../selftest/selftest.hpp"

int main() {
  static est::selftest::Result results[est::selftest::kMaxSections];
  const int n = est::selftest::run_all(results);
  int failures = 0;
  for (int i = 0; i < n; ++i) {
    std::printf("section %s 0x%016" PRIx64, results[i].name, results[i].digest);
    if (!results[i].ok()) {
      std::printf(" MISMATCH expected 0x%016" PRIx64, results[i].expected);
      ++failures;
    }
    std::printf("\n");
  }
  std::printf("firmware-selftest host digest 0x%016" PRIx64 " %s\n", est::selftest::combined(results, n),
              failures == 0 ? "PASS" : "FAIL");
  return failures == 0 ? 0 : 1;
}
