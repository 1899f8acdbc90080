#include <catch2/catch.hpp>

#include "selftest.hpp"

TEST_CASE("every self-test section reproduces its expected digest on the host", "[selftest]") {
  est::selftest::Result results[est::selftest::kMaxSections];
  const int n = est::selftest::run_all(results);
  REQUIRE(n >= 2);
  for (int i = 0; i < n; ++i) {
    INFO("section " << results[i].name << " digest 0x" << std::hex << results[i].digest << " expected 0x"
                    << results[i].expected);
    CHECK(results[i].ok());
  }
}

TEST_CASE("the self-test is deterministic run to run", "[selftest]") {
  est::selftest::Result first[est::selftest::kMaxSections], second[est::selftest::kMaxSections];
  const int n = est::selftest::run_all(first);
  REQUIRE(est::selftest::run_all(second) == n);
  CHECK(est::selftest::combined(first, n) == est::selftest::combined(second, n));
}
