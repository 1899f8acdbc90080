#pragma once
// exp for the hot loops, inline: fmath::exp's own fdlibm e_expf.c kernel, so the same bits as fmath::exp for every
// float (tested over a dense sample of every binade and at every float around the branch points in
// tests/test_inline_exp.cpp). Only the common case is inline: x in (-85, 0], where the result is a normal float;
// everything else (positive x, underflow, inf, NaN) calls fmath::exp. Inline, the compiler keeps the caller's
// registers across it and overlaps it with the surrounding work.
//
// Without branches on x's magnitude: fdlibm's three cases are one computation here. Its k = -1 case (|x| < 3 ln2 / 2)
// is the general reduction with t = -1 (x - (-1) hi and (-1) lo are exact, the same floats), and its k = 0 case
// (|x| <= ln2 / 2) is the general formula with hi = x, lo = 0 (x c / (c - 2) = -(x c / (2 - c)) exactly, and 0 - w is
// -w); only |x| < 2^-14, where fdlibm returns 1 + x, is a select. A branch per case costs a misprediction whenever
// x's magnitude is data-dependent, as the beam model's Gaussian over (z - z*) / sigma is.
#include <cstdint>
#include <cstring>

#include "est/math/fmath.hpp"

namespace est::imath {

inline float exp(float x) {
  if (!(x > -85.0f && x <= 0.0f)) return fmath::exp(x);
  constexpr float kLn2Hi = 0x1.62e4p-1f;
  constexpr float kLn2Lo = 0x1.7f7d1cp-20f;
  constexpr float kInvLn2 = 0x1.715476p+0f;
  constexpr float kP1 = 0xaaaaa8.0p-26f;
  constexpr float kP2 = -0xb55215.0p-32f;
  // x <= 0: k = round-half-away(x / ln2) = trunc(x / ln2 - 0.5), 0 for |x| <= ln2 / 2 (fdlibm's own rounding).
  std::uint32_t ix = 0;
  std::memcpy(&ix, &x, sizeof ix);
  const bool reduce = (ix & 0x7fffffffu) > 0x3eb17218u;  // |x| > ln2 / 2: fdlibm reduces only then
  const int k = reduce ? static_cast<int>(kInvLn2 * x + -0.5f) : 0;
  const auto t = static_cast<float>(k);
  const float hi = x - t * kLn2Hi;  // x itself for k = 0
  const float lo = t * kLn2Lo;      // 0 for k = 0
  const float r = hi - lo;
  const float r2 = r * r;
  const float c = r - r2 * (kP1 + r2 * kP2);
  const float y = 1.0f - ((lo - (r * c) / (2.0f - c)) - hi);
  // k >= -123 for x > -85: fmath::exp's normal-result branch, y 2^k with a normal 2^k.
  const std::uint32_t scale_bits = static_cast<std::uint32_t>(127 + k) << 23;
  float scale = 0.0f;
  std::memcpy(&scale, &scale_bits, sizeof scale);
  const float e = y * scale;
  return (ix & 0x7fffffffu) < 0x39000000u ? 1.0f + x : e;  // |x| < 2^-14: 1 + x within half an ULP
}

}  // namespace est::imath
