#include <catch2/catch.hpp>
#include <Eigen/Core>
#include <memory>
#include <vector>

#include "heap_guard.hpp"
#include "selftest.hpp"

// Positive controls: the guard must see the heap uses it is meant to catch, or its zeros prove nothing.
TEST_CASE("heap guard counts std::vector, new and a dynamic Eigen matrix", "[heap]") {
  {
    est::test::HeapGuard guard;
    std::vector<int> v(3);
    CHECK(guard.allocations() == 1u);
  }
  {
    est::test::HeapGuard guard;
    auto p = std::make_unique<int>(7);
    CHECK(guard.allocations() == 1u);
  }
  {
    est::test::HeapGuard guard;
    Eigen::MatrixXf m(4, 4);
    m.setZero();
    CHECK(guard.allocations() == 1u);
  }
}

TEST_CASE("the whole self-test workload runs without touching the heap", "[heap]") {
  est::selftest::Result results[est::selftest::kMaxSections];
  est::test::HeapGuard guard;
  const int n = est::selftest::run_all(results);
  const auto count = guard.allocations();
  CHECK(n >= 2);
  CHECK(count == 0u);
}
