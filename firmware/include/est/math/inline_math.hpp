#pragma once
// Inline sine, cosine and logarithm for the batched hot loops (motion sampling of whole particle sets): the same
// fdlibm kernels as est::fmath (k_sinf.c / k_cosf.c, degree 13 and 14; e_logf.c), but without fmath's handling of
// every float, so they inline and the compiler can schedule (and where it can, vectorize) them across particles.
// Pure float and integer arithmetic: the same bits on every target under -ffp-contract=off.
//
// - sincos_moderate(x): |x| <= 64 (several turns: a heading plus a step's change). Cody-Waite reduction by pi/2 with
//   a three-part constant; the reduction's tail is dropped, so the error is <= 2 ULP of the result or 2^-26
//   absolute (tested against long double in tests/test_inline_math.cpp); beyond |x| <= 64 it is not meaningful
//   (callers wrap angles first).
// - sincos_turns(u): sin and cos of 2 pi u for u in [0, 1) (Box-Muller's angle), reduced exactly: 4u is exact in
//   float, so the quadrant and the remaining fraction carry no reduction error at all.
// - wrap_angle_near(a): a in (-3 pi, 3 pi] wrapped to (-pi, pi] by one subtraction of a two-part 2 pi (within 2
//   ULP of pi of fmath::normalize_angle, tested).
// - select(c, a, b): c ? a : b by bit masks (see there).
// - log_normal_positive(x): log x for a positive normal float (e.g. a uniform on (0, 1]): fdlibm's e_logf
//   (reduction to [sqrt(1/2), sqrt(2)), degree-8 polynomial in s = f / (2 + f)), <= 1 ULP (tested); zero,
//   subnormal, negative and non-finite input is not handled.
#include <cstdint>
#include <cstring>

#include "est/math/fmath.hpp"

namespace est::imath {

// sin(x) and cos(x) for |x| <= pi/4 (fdlibm's float kernels, no tail).
inline float sin_kernel(float x) {
  constexpr float kS1 = -1.6666667163e-01f, kS2 = 8.3333337680e-03f, kS3 = -1.9841270114e-04f, kS4 = 2.7557314297e-06f,
                  kS5 = -2.5050759689e-08f, kS6 = 1.5896910177e-10f;
  const float z = x * x;
  const float v = z * x;
  const float r = kS2 + z * (kS3 + z * (kS4 + z * (kS5 + z * kS6)));
  return x + v * (kS1 + z * r);
}
inline float cos_kernel(float x) {
  constexpr float kC1 = 4.1666667908e-02f, kC2 = -1.3888889225e-03f, kC3 = 2.4801587642e-05f, kC4 = -2.7557314297e-07f,
                  kC5 = 2.0875723372e-09f, kC6 = -1.1359647598e-11f;
  const float z = x * x;
  const float r = z * (kC1 + z * (kC2 + z * (kC3 + z * (kC4 + z * (kC5 + z * kC6)))));
  return 1.0f - (0.5f * z - z * r);
}

// Picks (sin, cos) of q * pi/2 + r from the kernels' values at r; selects only, so loops around it vectorize.
inline void by_quadrant(std::int32_t q, float sk, float ck, float& s, float& c) {
  const bool swap = (q & 1) != 0;
  const float s0 = swap ? ck : sk;
  const float c0 = swap ? sk : ck;
  s = (q & 2) != 0 ? -s0 : s0;
  c = ((q + 1) & 2) != 0 ? -c0 : c0;
}

inline void sincos_moderate(float x, float& s, float& c) {
  // pi/2 = A + B + C with A, B of 16 significant bits: j * A and j * B exact for |j| < 2^8 (|x| <= 64 gives |j| <= 41).
  constexpr float kA = 0x1.921ep+0f, kB = 0x1.b544p-16f, kC = 0x1.0b4612p-34f, kTwoOverPi = 0x1.45f306p-1f;
  constexpr float kRound = 0x1.8p23f;
  const float j = (x * kTwoOverPi + kRound) - kRound;
  const float r = ((x - j * kA) - j * kB) - j * kC;
  by_quadrant(static_cast<std::int32_t>(j), sin_kernel(r), cos_kernel(r), s, c);
}

inline void sincos_turns(float u, float& s, float& c) {
  const float t = 4.0f * u;                     // exact
  const float q = (t + 0x1.8p23f) - 0x1.8p23f;  // nearest quadrant, ties to even: t - q in [-1/2, 1/2], exact
  const float r = (t - q) * kHalfPi;
  by_quadrant(static_cast<std::int32_t>(q), sin_kernel(r), cos_kernel(r), s, c);
}

inline float wrap_angle_near(float a) {
  constexpr float kTwoPiHi = 6.28318548202514648438f;   // float(2 pi), 1.7e-7 above 2 pi
  constexpr float kTwoPiLo = -1.7484555314695172e-07f;  // 2 pi - kTwoPiHi
  // k in {-1, 0, 1} as arithmetic, not a branch: GCC (under the default -ftrapping-math) will not if-convert a
  // conditional subtraction, and the loops calling this should vectorize. k = 0 returns a exactly.
  const float k = static_cast<float>(static_cast<std::int32_t>(a > kPi) - static_cast<std::int32_t>(a <= -kPi));
  return (a - k * kTwoPiHi) - k * kTwoPiLo;
}

// c ? a : b by bit masks: a select GCC vectorizes even where it would not speculate the arithmetic producing a.
inline float select(bool c, float a, float b) {
#if defined(__arm__)
  return c ? a : b;  // Cortex-M: a conditional move (it + vmov), cheaper than the masks through core registers
#else
  std::uint32_t ua = 0, ub = 0;
  std::memcpy(&ua, &a, sizeof ua);
  std::memcpy(&ub, &b, sizeof ub);
  const std::uint32_t m = 0u - static_cast<std::uint32_t>(c);
  const std::uint32_t r = (ua & m) | (ub & ~m);
  float out = 0.0f;
  std::memcpy(&out, &r, sizeof out);
  return out;
#endif
}

inline float log_normal_positive(float x) {
  constexpr float kLn2Hi = 6.9313812256e-01f, kLn2Lo = 9.0580006145e-06f;
  constexpr float kLg1 = 0xaaaaaa.0p-24f, kLg2 = 0xccce13.0p-25f, kLg3 = 0x91e9ee.0p-25f, kLg4 = 0xf89e26.0p-26f;
  std::uint32_t ix = 0;
  std::memcpy(&ix, &x, sizeof ix);
  ix += 0x3f800000u - 0x3f3504f3u;  // reduce x to [sqrt(1/2), sqrt(2)) times 2^k
  const std::int32_t k = static_cast<std::int32_t>(ix >> 23) - 0x7f;
  ix = (ix & 0x007fffffu) + 0x3f3504f3u;
  float m = 0.0f;
  std::memcpy(&m, &ix, sizeof m);
  const float f = m - 1.0f;
  const float s = f / (2.0f + f);
  const float z = s * s;
  const float w = z * z;
  const float r = z * (kLg1 + w * kLg3) + w * (kLg2 + w * kLg4);
  const float hfsq = 0.5f * f * f;
  const float dk = static_cast<float>(k);
  return s * (hfsq + r) + dk * kLn2Lo - hfsq + f + dk * kLn2Hi;
}

}  // namespace est::imath
