#include <catch2/catch.hpp>
#include <cstdint>

#include "est/eigen.hpp"
#include "est/util/digest.hpp"

namespace {
std::uint64_t fnv1a_bytes(const unsigned char* p, std::size_t n) {
  std::uint64_t h = 0xcbf29ce484222325ull;
  for (std::size_t i = 0; i < n; ++i) {
    h ^= p[i];
    h *= 0x100000001b3ull;
  }
  return h;
}
}  // namespace

TEST_CASE("digest is FNV-1a 64 over little-endian words", "[digest]") {
  const unsigned char a[] = {'a'};
  CHECK(fnv1a_bytes(a, 1) == 0xaf63dc4c8601ec8cull);  // published FNV-1a test vector for "a"
  const unsigned char word[] = {0x78, 0x56, 0x34, 0x12};
  est::Digest d;
  d.add_u32(0x12345678u);
  CHECK(d.value() == fnv1a_bytes(word, 4));
}

TEST_CASE("digest tells apart floats that compare equal but differ in bits", "[digest]") {
  est::Digest pos, neg;
  pos.add(0.0f);
  neg.add(-0.0f);
  CHECK(pos.value() != neg.value());
}

TEST_CASE("matrix digest is column-major and covers every entry", "[digest]") {
  Eigen::Matrix2f m;
  m << 1.0f, 2.0f, 3.0f, 4.0f;
  est::Digest by_hand, by_matrix;
  for (float v : {1.0f, 3.0f, 2.0f, 4.0f}) by_hand.add(v);
  by_matrix.add_matrix(m);
  CHECK(by_hand.value() == by_matrix.value());
}
