#pragma once
// Float lanes for the host's batched particle loops: GCC vector types (kLanes floats, one SSE2 register on the x86-64
// baseline) and the firmware's scalar kernels written lane-wise.
// Every function here gives, in every lane, the bits of the scalar function it names, on every input it accepts:
// the same IEEE 754 operations in the same order (no FMA under -ffp-contract=off, no reassociation without
// -ffast-math), selects instead of branches, truncating conversions only of values the scalar code converts. So a
// loop over particles vectorized with these gives the board's scalar bits (tests/test_lanes.cpp compares them bit
// for bit; the determinism digests compare host and board). Used where a target has vector registers (not on the
// Cortex-M boards, whose single-issue FPU gains nothing from them: the boards keep the scalar loops).
//
// - sincos(x): fmath::sincos's bits for |x| < 200 (its Cody-Waite path; the lanes outside, and NaN or inf, are
//   reported in the mask for the caller to take fmath::sincos).
// - sin_kernel, sincos_moderate, wrap_angle_near: est::imath's bits (est/math/inline_math.hpp) where those are
//   defined.
// - exp(x): imath::exp's (and so fmath::exp's) bits for x in (-85, 0] (the lanes outside reported in the mask).
// - normal_cdf(z): est::normal_cdf's bits for every z.
#include <cstdint>
#include <cstring>

#include "est/math/fmath.hpp"
#include "est/math/inline_exp.hpp"
#include "est/math/inline_math.hpp"

namespace est::lanes {

// Four: one SSE2 register on the x86-64 baseline (a wider vector in a signature would change the ABI there).
inline constexpr std::uint32_t kLanes = 4;
using F = float __attribute__((vector_size(4 * kLanes)));
using I = std::int32_t __attribute__((vector_size(4 * kLanes)));
using U = std::uint32_t __attribute__((vector_size(4 * kLanes)));

inline F load(const float* p) {
  F v;
  std::memcpy(&v, p, sizeof v);
  return v;
}
inline void store(float* p, F v) { std::memcpy(p, &v, sizeof v); }
inline U bits(F v) {
  U u;
  std::memcpy(&u, &v, sizeof u);
  return u;
}
inline F from_bits(U u) {
  F v;
  std::memcpy(&v, &u, sizeof v);
  return v;
}
inline F splat(float v) { return F{} + v; }
// m ? a : b per lane (m: all ones or zero, as comparisons give).
inline F select(I m, F a, F b) { return m ? a : b; }
inline F abs(F x) { return from_bits(bits(x) & 0x7fffffffu); }
// Lanes whose mask is set.
inline std::uint32_t count(I m) {
  std::uint32_t c = 0;
  for (std::uint32_t j = 0; j < kLanes; ++j) c += m[j] != 0 ? 1u : 0u;
  return c;
}
inline bool any(I m) { return count(m) != 0u; }

// The scalar forms under the same names, so one template body serves one particle (float, bool masks: the board's
// loop, and the host's remainder) and kLanes of them (F, I masks).
template <class T>
inline T broadcast(float v) {
  if constexpr (sizeof(T) == sizeof(float)) {
    return v;
  } else {
    return splat(v);
  }
}
inline float abs(float x) { return fmath::abs(x); }
inline float select(bool m, float a, float b) { return imath::select(m, a, b); }
inline std::uint32_t count_false(bool m) { return m ? 0u : 1u; }
inline std::uint32_t count_false(I m) { return kLanes - count(m); }
inline float sin_kernel(float x) { return imath::sin_kernel(x); }
inline void sincos_moderate(float x, float& s, float& c) { imath::sincos_moderate(x, s, c); }
inline float wrap_angle_near(float a) { return imath::wrap_angle_near(a); }

// ---------------------------------------------------------------------------------------------------------------
// est::imath (inline_math.hpp), lane-wise.

inline F sin_kernel(F x) {
  constexpr float kS1 = -1.6666667163e-01f, kS2 = 8.3333337680e-03f, kS3 = -1.9841270114e-04f, kS4 = 2.7557314297e-06f,
                  kS5 = -2.5050759689e-08f, kS6 = 1.5896910177e-10f;
  const F z = x * x;
  const F v = z * x;
  const F r = kS2 + z * (kS3 + z * (kS4 + z * (kS5 + z * kS6)));
  return x + v * (kS1 + z * r);
}
inline F cos_kernel(F x) {
  constexpr float kC1 = 4.1666667908e-02f, kC2 = -1.3888889225e-03f, kC3 = 2.4801587642e-05f, kC4 = -2.7557314297e-07f,
                  kC5 = 2.0875723372e-09f, kC6 = -1.1359647598e-11f;
  const F z = x * x;
  const F r = z * (kC1 + z * (kC2 + z * (kC3 + z * (kC4 + z * (kC5 + z * kC6)))));
  return 1.0f - (0.5f * z - z * r);
}
// imath::by_quadrant: negation flips the sign bit, as the scalar negation does.
inline void by_quadrant(I q, F sk, F ck, F& s, F& c) {
  const I swap = (q & 1) != 0;
  const F s0 = swap ? ck : sk;
  const F c0 = swap ? sk : ck;
  s = (q & 2) != 0 ? -s0 : s0;
  c = ((q + 1) & 2) != 0 ? -c0 : c0;
}
inline void sincos_moderate(F x, F& s, F& c) {
  constexpr float kA = 0x1.921ep+0f, kB = 0x1.b544p-16f, kC = 0x1.0b4612p-34f, kTwoOverPi = 0x1.45f306p-1f;
  constexpr float kRound = 0x1.8p23f;
  const F j = (x * kTwoOverPi + kRound) - kRound;
  const F r = ((x - j * kA) - j * kB) - j * kC;
  by_quadrant(__builtin_convertvector(j, I), sin_kernel(r), cos_kernel(r), s, c);
}
inline F wrap_angle_near(F a) {
  constexpr float kTwoPiHi = 6.28318548202514648438f;
  constexpr float kTwoPiLo = -1.7484555314695172e-07f;
  // Comparisons give -1 where true: (a <= -pi) - (a > pi) is the scalar's (a > pi) - (a <= -pi).
  const F k = __builtin_convertvector((a <= -kPi) - (a > kPi), F);
  return (a - k * kTwoPiHi) - k * kTwoPiLo;
}

// imath::exp (inline_exp.hpp) on its inline range x in (-85, 0], lane-wise: fmath::exp's bits there. The lanes
// outside are reported in the mask for the caller to take imath::exp.
inline I exp(F x, F& e) {
  constexpr float kLn2Hi = 0x1.62e4p-1f;
  constexpr float kLn2Lo = 0x1.7f7d1cp-20f;
  constexpr float kInvLn2 = 0x1.715476p+0f;
  constexpr float kP1 = 0xaaaaa8.0p-26f;
  constexpr float kP2 = -0xb55215.0p-32f;
  const U ax = bits(x) & 0x7fffffffu;
  const I reduce = ax > 0x3eb17218u;
  const I k = reduce ? __builtin_convertvector(kInvLn2 * x + -0.5f, I) : I{};
  const F t = __builtin_convertvector(k, F);
  const F hi = x - t * kLn2Hi;
  const F lo = t * kLn2Lo;
  const F r = hi - lo;
  const F r2 = r * r;
  const F c = r - r2 * (kP1 + r2 * kP2);
  const F y = 1.0f - ((lo - (r * c) / (2.0f - c)) - hi);
  const F scale = from_bits(__builtin_convertvector(127 + k, U) << 23);
  e = (ax < 0x39000000u) ? 1.0f + x : y * scale;
  return (x > -85.0f) & (x <= 0.0f);
}

// The lanes where est::normal_cdf computes its tail (|z| / sqrt 2 <= 9); beyond, it is 0 or 1 (and 0.5 for NaN).
inline I normal_cdf_computes(F z) { return abs(z) * 0.70710678118654752440f <= 9.0f; }

// est::normal_cdf (est/math/normal.hpp) lane-wise: its bits for every finite z (its exp's argument is in [-81, 0],
// exp's inline range); NaN gives 0.5, as there.
inline F normal_cdf(F z) {
  const I far = ~normal_cdf_computes(z);  // NaN too: replaced below
  const F xs = far ? splat(0.0f) : abs(z) * 0.70710678118654752440f;  // keeps exp's argument in range
  const F t = 1.0f / (1.0f + 0.3275911f * xs);
  const F poly =
      t * (0.254829592f + t * (-0.284496736f + t * (1.421413741f + t * (-1.453152027f + t * 1.061405429f))));
  F e;
  exp(-xs * xs, e);
  const F tail = 0.5f * poly * e;
  const I neg = z < 0.0f;
  const F near = neg ? tail : 1.0f - tail;
  const F ends = neg ? splat(0.0f) : splat(1.0f);
  return (z == z) ? (far ? ends : near) : splat(0.5f);
}

// ---------------------------------------------------------------------------------------------------------------
// fmath::sincos (src/fmath.cpp) on its Cody-Waite path, lane-wise: the same reduction with its tail, the same
// kernels with a tail, the same quadrant table and sign.

namespace detail {

inline F two_sum_err(F a, F b, F s) {
  const F bb = s - a;
  return (a - (s - bb)) + (b - bb);
}
inline F sin_kernel_tail(F x, F y) {
  constexpr float kS1 = -1.6666667163e-01f, kS2 = 8.3333337680e-03f, kS3 = -1.9841270114e-04f,
                  kS4 = 2.7557314297e-06f, kS5 = -2.5050759689e-08f, kS6 = 1.5896910177e-10f;
  const F z = x * x;
  const F v = z * x;
  const F r = kS2 + z * (kS3 + z * (kS4 + z * (kS5 + z * kS6)));
  return x - ((z * (0.5f * y - v * r) - y) - v * kS1);
}
inline F cos_kernel_tail(F x, F y) {
  constexpr float kC1 = 4.1666667908e-02f, kC2 = -1.3888889225e-03f, kC3 = 2.4801587642e-05f,
                  kC4 = -2.7557314297e-07f, kC5 = 2.0875723372e-09f, kC6 = -1.1359647598e-11f;
  const U ix = bits(x) & 0x7fffffffu;
  const F z = x * x;
  const F r = z * (kC1 + z * (kC2 + z * (kC3 + z * (kC4 + z * (kC5 + z * kC6)))));
  const F near = 1.0f - (0.5f * z - (z * r - x * y));  // |x| < 0.3
  const F qx = (ix > 0x3f480000u) ? splat(0.28125f) : from_bits((ix - 0x01000000u) & 0xffffff00u);
  const F hz = 0.5f * z - qx;
  const F a = 1.0f - qx;
  const F far = a - (hz - (z * r - x * y));
  return (ix < 0x3e99999au) ? near : far;
}

}  // namespace detail

// s, c = fmath::sincos(x) in every lane where the returned mask is set (|x| < 200, finite); the other lanes hold
// garbage for the caller to replace.
inline I sincos(F x, F& s, F& c) {
  constexpr float kPio2A = 0x1.921ep+0f, kPio2B = 0x1.b544p-16f, kPio2C = 0x1.0b4612p-34f;
  constexpr float kTwoOverPi = 0x1.45f306p-1f, kRoundMagic = 0x1.8p23f;
  const U ax = bits(x) & 0x7fffffffu;
  const I small = ax <= 0x3f490fdau;  // |x| <= pi/4: the kernels at x, no reduction
  const F a = from_bits(ax);
  // Cody-Waite on |x| (fmath's reduce_cody_waite, then normalized()).
  const F j = (a * kTwoOverPi + kRoundMagic) - kRoundMagic;
  const F r1 = a - j * kPio2A;
  const F w = j * kPio2B;
  const F r2 = r1 - w;
  const F e2 = detail::two_sum_err(r1, -w, r2);
  const F cc = j * kPio2C;
  const F r3 = r2 - cc;
  const F e3 = detail::two_sum_err(r2, -cc, r3);
  const F lo0 = e2 + e3;
  const F h = r3 + lo0;
  const F l = lo0 - (h - r3);
  const F zero = {};
  const F hi = small ? x : h;
  const F lo = small ? zero : l;
  const I q = small ? I{} : (__builtin_convertvector(j, I) & 3);
  const F sk = detail::sin_kernel_tail(hi, lo);
  const F ck = detail::cos_kernel_tail(hi, lo);
  // Quadrant 0: (sk, ck), 1: (ck, -sk), 2: (-sk, -ck), 3: (-ck, sk); then the sign of x (not on the small path).
  F sa, ca;
  by_quadrant(q, sk, ck, sa, ca);
  s = ((small == 0) & (x < 0.0f)) ? -sa : sa;
  c = ca;
  return ax < 0x43480000u;  // |x| < 200 (finite)
}

}  // namespace est::lanes
