#include <catch2/catch.hpp>

#include <cstdint>
#include <cstring>

#include "est/math/fmath.hpp"
#include "est/math/inline_exp.hpp"

namespace {

float from_bits(std::uint32_t b) {
  float x = 0.0f;
  std::memcpy(&x, &b, sizeof x);
  return x;
}
std::uint32_t bits(float x) {
  std::uint32_t b = 0;
  std::memcpy(&b, &x, sizeof b);
  return b;
}

}  // namespace

TEST_CASE("inline exp gives fmath::exp's bits on its inline range (-85, 0]", "[inline_exp]") {
  // Every 97th float bit pattern from -0 down to -85 (11 million of the 1.1 billion, every binade), all the same bits.
  const std::uint32_t lo = bits(-0.0f), hi = bits(-85.0f);
  std::uint32_t mismatches = 0, tried = 0;
  for (std::uint32_t b = lo; b <= hi; b += 97u) {
    const float x = from_bits(b);
    if (bits(est::imath::exp(x)) != bits(est::fmath::exp(x))) ++mismatches;
    ++tried;
  }
  CHECK(tried > 11000000u);
  CHECK(mismatches == 0u);
}

TEST_CASE("inline exp matches fmath::exp at every float around its branch points", "[inline_exp]") {
  // 2^-14 (the 1 + x branch), ln2 / 2 and 3 ln2 / 2 (k = 0 and k = -1), -85 (the inline limit) and 0.
  for (float c : {-0x1p-14f, -0.34657359f, -1.03972077f, -85.0f, -0.0f}) {
    const std::uint32_t b0 = bits(c);
    for (std::uint32_t d = 0; d < 4000u; ++d) {
      const float x = from_bits(b0 - 2000u + d);
      INFO("x = " << x);
      REQUIRE(bits(est::imath::exp(x)) == bits(est::fmath::exp(x)));
    }
  }
}

TEST_CASE("inline exp hands every other input to fmath::exp", "[inline_exp]") {
  const float nan = __builtin_nanf(""), inf = __builtin_inff();
  for (float x : {0.0f, 1e-30f, 0.5f, 3.0f, 88.0f, 89.0f, -86.0f, -90.0f, -103.9f, -104.0f, -1e30f, inf, -inf}) {
    INFO("x = " << x);
    CHECK(bits(est::imath::exp(x)) == bits(est::fmath::exp(x)));
  }
  CHECK(est::imath::exp(nan) != est::imath::exp(nan));  // NaN in, NaN out
  CHECK(est::imath::exp(-inf) == 0.0f);
  CHECK(est::imath::exp(0.0f) == 1.0f);
}
