#pragma once
// Counts heap allocations made by this thread while a HeapGuard is alive: "no heap after start-up", shown on the
// host. malloc and friends are replaced in heap_guard.cpp and forward to glibc's __libc_* entry points.
#include <cstddef>

namespace est::test {

class HeapGuard {
 public:
  HeapGuard();
  ~HeapGuard();
  HeapGuard(const HeapGuard&) = delete;
  HeapGuard& operator=(const HeapGuard&) = delete;
  std::size_t allocations() const;

 private:
  std::size_t start_;
};

}  // namespace est::test
