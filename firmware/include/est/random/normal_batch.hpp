#pragma once
// Standard normal draws in bulk for the batched particle-filter loops: Box-Muller with BOTH outputs of every pair
// used (half the uniforms and logarithms of sample_normal, which keeps one of each pair), and the angle's sine and
// cosine from imath::sincos_turns, whose reduction of 2 pi u is exact (4 u is exact in float). No table, no
// rejection: a fixed number of draws (two uniforms per pair), bounded time, the same bits on every target.
//
// Accuracy: each value is R cos(2 pi u2) or R sin(2 pi u2), R = sqrt(-2 log u1), with imath's log (<= 1 ULP),
// sqrt (correctly rounded) and the kernels (<= 2 ULP): a few ULP from the exact transform of the two uniforms.
// The uniforms have 24 bits, so |x| <= sqrt(2 ln 2^24) = 5.77 (the tail beyond has probability 8e-9), like
// sample_normal_box_muller. Distribution tested in tests/test_normal_batch.cpp (KS at 0.001, moments).
#include <cstdint>

#include "est/math/fmath.hpp"
#include "est/math/inline_math.hpp"
#include "est/random/xoshiro128.hpp"

namespace est {

// out[0 .. n-1] ~ N(0, 1), independent; draws 2 ceil(n / 2) uniforms, in order. Pair k gives out[k] and
// out[h + k] (h = n / 2), so the second pass runs over contiguous arrays and vectorizes.
inline void fill_standard_normals(Rng& rng, float* out, std::uint32_t n) {
  const std::uint32_t h = n / 2u;
  // Pass 1 (sequential: the generator): u1 of pair k in out[k], its u2 in out[h + k].
  for (std::uint32_t k = 0; k < h; ++k) {
    out[k] = rng.uniform_open_zero();
    out[h + k] = rng.uniform();
  }
  if ((n & 1u) != 0u) {  // odd n: the last value is the cosine half of one more pair
    const float u1 = rng.uniform_open_zero();
    float s = 0.0f, c = 0.0f;
    imath::sincos_turns(rng.uniform(), s, c);
    out[n - 1u] = fmath::sqrt(-2.0f * imath::log_normal_positive(u1)) * c;
  }
  // Pass 2 (independent per pair), in three loops: the logarithm and the rotation vectorize; the square root stays
  // apart because GCC keeps errno semantics for it (a branch) unless built with -fno-math-errno.
  float* __restrict first = out;
  float* __restrict second = out + h;
  for (std::uint32_t k = 0; k < h; ++k) first[k] = -2.0f * imath::log_normal_positive(first[k]);
  for (std::uint32_t k = 0; k < h; ++k) first[k] = fmath::sqrt(first[k]);  // >= 0 (u1 <= 1)
  for (std::uint32_t k = 0; k < h; ++k) {
    float s = 0.0f, c = 0.0f;
    imath::sincos_turns(second[k], s, c);
    const float r = first[k];
    first[k] = r * c;
    second[k] = r * s;
  }
}

}  // namespace est
