// The firmware's own float math: pure float and integer arithmetic, no libm, no long double, no double, so the
// same source gives the same bits on glibc hosts and newlib boards (given -ffp-contract=off, which the build sets).
// Algorithms: reduction by pi/2 (Cody-Waite below 200, integer Payne-Hanek above, both keeping a tail) into fdlibm's
// single-precision sin/cos kernels; fdlibm's single-precision atanf, atan2f, expf and logf (Sun Microsystems,
// FreeBSD msun). No-libm is checked on the board images by firmware/target/mps2/check_no_libm.cmake.
// Accuracy per function is stated in est/math/fmath.hpp and measured in tests/test_fmath.cpp.
#include "est/math/fmath.hpp"

#include <cstring>

namespace est::fmath {
namespace {

std::uint32_t bits_of(float x) {
  std::uint32_t b = 0;
  std::memcpy(&b, &x, sizeof b);
  return b;
}

float from_bits(std::uint32_t b) {
  float x = 0.0f;
  std::memcpy(&x, &b, sizeof x);
  return x;
}

constexpr std::uint32_t kAbsMask = 0x7fffffffu;
constexpr std::uint32_t kInfBits = 0x7f800000u;

// ---------------------------------------------------------------------------------------------------------------
// Reduction by pi/2: x = quadrant * pi/2 + (hi + lo) (mod 2 pi), |hi| <= pi/4 (plus a few ULP at quadrant
// boundaries), lo below half an ULP of hi. The tail matters: an error of half an ULP in r alone can cost a whole
// ULP of sin(r) where sin(r) falls into the binade below r.

struct Reduced {
  float hi;
  float lo;
  std::uint32_t quadrant;  // 0..3
};

// a + b = s + err exactly (Knuth's TwoSum, no precondition on the magnitudes).
float two_sum_err(float a, float b, float s) {
  const float bb = s - a;
  return (a - (s - bb)) + (b - bb);
}

Reduced normalized(float hi, float lo, std::uint32_t quadrant) {
  const float h = hi + lo;
  return {h, lo - (h - hi), quadrant};
}

// Cody-Waite: pi/2 = kPio2A + kPio2B + kPio2C (to 2^-59), A and B with 16 significant bits each, so j * A and j * B
// are exact for j < 2^8, and x - j * A is exact by Sterbenz's lemma; the two remaining subtractions keep their
// rounding errors (TwoSum). Absolute error of hi + lo below 2^-48: for |x| < 200 (j <= 128).
constexpr float kPio2A = 0x1.921ep+0f;
constexpr float kPio2B = 0x1.b544p-16f;
constexpr float kPio2C = 0x1.0b4612p-34f;
constexpr float kTwoOverPi = 0x1.45f306p-1f;
constexpr float kCodyWaiteLimit = 200.0f;
// Adding then subtracting 1.5 * 2^23 rounds a float below 2^22 to the nearest integer (ties to even).
constexpr float kRoundMagic = 0x1.8p23f;

Reduced reduce_cody_waite(float x) {
  const float j = (x * kTwoOverPi + kRoundMagic) - kRoundMagic;
  const float r1 = x - j * kPio2A;
  const float w = j * kPio2B;
  const float r2 = r1 - w;
  const float e2 = two_sum_err(r1, -w, r2);
  const float c = j * kPio2C;
  const float r3 = r2 - c;
  const float e3 = two_sum_err(r2, -c, r3);
  const auto n = static_cast<std::int32_t>(j);
  return normalized(r3, e2 + e3, static_cast<std::uint32_t>(n) & 3u);
}

// 2/pi in binary, 288 bits, after one zero word so that the window below may start before the binary point.
constexpr std::uint32_t kTwoOverPiBits[] = {0x00000000u, 0xA2F9836Eu, 0x4E441529u, 0xFC2757D1u, 0xF534DDC0u,
                                            0xDB629599u, 0x3C439041u, 0xFE5163ABu, 0xDEBBC561u, 0xB7246E3Au};

// 32 bits of kTwoOverPiBits starting at bit offset `bit` (bit 0 is the most significant bit of the first word).
std::uint32_t two_over_pi_word(std::uint32_t bit) {
  const std::uint32_t k = bit >> 5;
  const std::uint32_t sh = bit & 31u;
  if (sh == 0u) return kTwoOverPiBits[k];
  return (kTwoOverPiBits[k] << sh) | (kTwoOverPiBits[k + 1u] >> (32u - sh));
}

// Payne-Hanek in integer arithmetic, exact for every finite float >= 1: with x = m * 2^s (m the 24-bit
// significand), x * 2/pi mod 4 = m * W * 2^-94 mod 4 where W is the 96-bit window of 2/pi starting at bit s - 1
// (earlier bits only add multiples of 4). The 2.62 fixed-point fraction keeps at least 33 exact significant bits
// (no float lies closer than 2^-29 quadrants to a multiple of pi/2; the same scheme as ARM optimized-routines'
// sinf), the product by pi/2 is taken to 64 bits, and its top 24 bits and the rest become hi and lo.
Reduced reduce_payne_hanek(std::uint32_t abs_bits) {
  const std::uint32_t e = abs_bits >> 23;
  const std::uint32_t m = (abs_bits & 0x007fffffu) | 0x00800000u;
  const std::uint32_t first = e - 120u;  // array bit of stream bit s - 1, with s = e - 150
  const std::uint32_t w0 = two_over_pi_word(first);
  const std::uint32_t w1 = two_over_pi_word(first + 32u);
  const std::uint32_t w2 = two_over_pi_word(first + 64u);
  const std::uint64_t u = (static_cast<std::uint64_t>(m * w0) << 32) + static_cast<std::uint64_t>(m) * w1 +
                          ((static_cast<std::uint64_t>(m) * w2) >> 32);
  // Nearest quadrant; the wrap-around of u + 2^61 near 4 quadrants is the right answer modulo 4.
  const std::uint64_t n = (u + (std::uint64_t{1} << 61)) >> 62;
  const auto f = static_cast<std::int64_t>(u - (n << 62));  // fraction of a quadrant, 2^-62 units, |f| <= 2^61
  const std::uint32_t quadrant = static_cast<std::uint32_t>(n) & 3u;
  if (f == 0) return {0.0f, 0.0f, quadrant};
  const std::uint64_t a = f < 0 ? static_cast<std::uint64_t>(-f) : static_cast<std::uint64_t>(f);
  const int lz = __builtin_clzll(a);  // >= 2
  const std::uint64_t an = a << lz;
  // q = top 64 bits of an * round(pi/2 * 2^62), so r = a * 2^-62 * pi/2 = q * 2^(-60 - lz); q in [2^61, 2^63).
  constexpr std::uint64_t kPio2Q62 = 0x6487ed5110b4611aull;
  const std::uint64_t ah = an >> 32, al = an & 0xffffffffu;
  const std::uint64_t ph = kPio2Q62 >> 32, pl = kPio2Q62 & 0xffffffffu;
  const std::uint64_t q = ah * ph + ((ah * pl) >> 32) + ((al * ph) >> 32);
  const int sh = 40 - __builtin_clzll(q);  // keep 24 bits in hi
  const std::uint64_t top = q >> sh;
  const std::uint64_t rest = q - (top << sh);
  // Powers of two 2^(sh - 60 - lz) and 2^(-60 - lz): normal, since lz <= 63.
  const float scale_lo = from_bits(static_cast<std::uint32_t>(127 - 60 - lz) << 23);
  const float scale_hi = from_bits(static_cast<std::uint32_t>(127 + sh - 60 - lz) << 23);
  const float hi = static_cast<float>(static_cast<std::uint32_t>(top)) * scale_hi;  // exact
  const float lo = static_cast<float>(rest) * scale_lo;
  const Reduced r = normalized(hi, lo, quadrant);
  return f < 0 ? Reduced{-r.hi, -r.lo, quadrant} : r;
}

// |x| > pi/4, finite.
Reduced reduce_pio2(float abs_x) {
  if (abs_x < kCodyWaiteLimit) return reduce_cody_waite(abs_x);
  return reduce_payne_hanek(bits_of(abs_x));
}

// ---------------------------------------------------------------------------------------------------------------
// Kernels on |x| <= pi/4 with a tail y (|y| < ulp(x)): fdlibm's single-precision k_sinf.c and k_cosf.c, degree 13
// and 14 (coefficients the double minimax ones rounded to float, so their truncation error is far below an ULP).

float sin_kernel(float x, float y) {
  constexpr float kS1 = -1.6666667163e-01f, kS2 = 8.3333337680e-03f, kS3 = -1.9841270114e-04f,
                  kS4 = 2.7557314297e-06f, kS5 = -2.5050759689e-08f, kS6 = 1.5896910177e-10f;
  const float z = x * x;
  const float v = z * x;
  const float r = kS2 + z * (kS3 + z * (kS4 + z * (kS5 + z * kS6)));
  // sin(x + y) = sin(x) + y cos(x) to first order in y, with cos(x) ~ 1 - z/2.
  return x - ((z * (0.5f * y - v * r) - y) - v * kS1);
}

float cos_kernel(float x, float y) {
  constexpr float kC1 = 4.1666667908e-02f, kC2 = -1.3888889225e-03f, kC3 = 2.4801587642e-05f,
                  kC4 = -2.7557314297e-07f, kC5 = 2.0875723372e-09f, kC6 = -1.1359647598e-11f;
  const std::uint32_t ix = bits_of(x) & kAbsMask;
  const float z = x * x;
  const float r = z * (kC1 + z * (kC2 + z * (kC3 + z * (kC4 + z * (kC5 + z * kC6)))));
  // cos(x + y) = cos(x) - y sin(x) to first order in y, with sin(x) ~ x.
  if (ix < 0x3e99999au) return 1.0f - (0.5f * z - (z * r - x * y));  // |x| < 0.3
  // Otherwise 1 - z/2 loses bits: take qx ~ |x|/4 (or 0.28125) out of both parts first, as fdlibm's k_cos does;
  // qx keeps 16 significant bits so that 1 - qx is exact.
  const float qx = ix > 0x3f480000u ? 0.28125f : from_bits((ix - 0x01000000u) & 0xffffff00u);
  const float hz = 0.5f * z - qx;
  const float a = 1.0f - qx;
  return a - (hz - (z * r - x * y));
}

constexpr float kQuietNaN() { return __builtin_nanf(""); }

}  // namespace

float sin(float x) {
  const std::uint32_t ax = bits_of(x) & kAbsMask;
  if (ax >= kInfBits) return kQuietNaN();
  if (ax <= 0x3f490fdau) return sin_kernel(x, 0.0f);  // |x| <= pi/4, including +-0 and subnormals
  const Reduced red = reduce_pio2(from_bits(ax));
  float s = 0.0f;
  switch (red.quadrant) {
    case 0u: s = sin_kernel(red.hi, red.lo); break;
    case 1u: s = cos_kernel(red.hi, red.lo); break;
    case 2u: s = -sin_kernel(red.hi, red.lo); break;
    default: s = -cos_kernel(red.hi, red.lo); break;
  }
  return x < 0.0f ? -s : s;
}

float cos(float x) {
  const std::uint32_t ax = bits_of(x) & kAbsMask;
  if (ax >= kInfBits) return kQuietNaN();
  if (ax <= 0x3f490fdau) return cos_kernel(x, 0.0f);
  const Reduced red = reduce_pio2(from_bits(ax));
  switch (red.quadrant) {
    case 0u: return cos_kernel(red.hi, red.lo);
    case 1u: return -sin_kernel(red.hi, red.lo);
    case 2u: return -cos_kernel(red.hi, red.lo);
    default: return sin_kernel(red.hi, red.lo);
  }
}

void sincos(float x, float& s, float& c) {
  const std::uint32_t ax = bits_of(x) & kAbsMask;
  if (ax >= kInfBits) {
    s = kQuietNaN();
    c = kQuietNaN();
    return;
  }
  if (ax <= 0x3f490fdau) {
    s = sin_kernel(x, 0.0f);
    c = cos_kernel(x, 0.0f);
    return;
  }
  const Reduced red = reduce_pio2(from_bits(ax));
  const float sk = sin_kernel(red.hi, red.lo);
  const float ck = cos_kernel(red.hi, red.lo);
  float sa = 0.0f;
  switch (red.quadrant) {
    case 0u: sa = sk; c = ck; break;
    case 1u: sa = ck; c = -sk; break;
    case 2u: sa = -sk; c = -ck; break;
    default: sa = -ck; c = sk; break;
  }
  s = x < 0.0f ? -sa : sa;
}

// ---------------------------------------------------------------------------------------------------------------
// atan: fdlibm s_atanf.c. Reduce |x| to |t| <= 7/16 around the breakpoints 0, 1/2, 1, 3/2, inf, where
// atan(x) = atan(c) + atan(t) with atan(c) stored as hi + lo, then an odd minimax polynomial of degree 11.

float atan(float x) {
  constexpr float kAtanHi[] = {0x1.dac67p-2f, 0x1.921fb4p-1f, 0x1.f730bcp-1f, 0x1.921fb4p+0f};
  constexpr float kAtanLo[] = {0x1.586ed2p-28f, 0x1.4442dp-25f, 0x1.281f68p-25f, 0x1.4442dp-24f};
  constexpr float kAT0 = 3.3333328366e-01f, kAT1 = -1.9999158382e-01f, kAT2 = 1.4253635705e-01f,
                  kAT3 = -1.0648017377e-01f, kAT4 = 6.1687607318e-02f;
  const std::uint32_t hx = bits_of(x);
  const std::uint32_t ix = hx & kAbsMask;
  const bool negative = (hx >> 31) != 0u;
  if (ix >= 0x4c800000u) {  // |x| >= 2^26: atan(x) rounds to +-pi/2
    if (ix > kInfBits) return kQuietNaN();
    return negative ? -(kAtanHi[3] + kAtanLo[3]) : kAtanHi[3] + kAtanLo[3];
  }
  int id = -1;
  float t = x;
  if (ix < 0x3ee00000u) {              // |x| < 7/16
    if (ix < 0x39800000u) return x;    // |x| < 2^-12: atan(x) = x to within half an ULP
  } else {
    t = from_bits(ix);
    if (ix < 0x3f980000u) {            // |x| < 19/16
      if (ix < 0x3f300000u) {          // 7/16 <= |x| < 11/16
        id = 0;
        t = (2.0f * t - 1.0f) / (2.0f + t);
      } else {                         // 11/16 <= |x| < 19/16
        id = 1;
        t = (t - 1.0f) / (t + 1.0f);
      }
    } else if (ix < 0x401c0000u) {     // 19/16 <= |x| < 39/16
      id = 2;
      t = (t - 1.5f) / (1.0f + 1.5f * t);
    } else {                           // 39/16 <= |x| < 2^26
      id = 3;
      t = -1.0f / t;
    }
  }
  const float z = t * t;
  const float w = z * z;
  // Odd and even parts of the polynomial in z, evaluated separately (fdlibm's split).
  const float s1 = z * (kAT0 + w * (kAT2 + w * kAT4));
  const float s2 = w * (kAT1 + w * kAT3);
  if (id < 0) return t - t * (s1 + s2);
  const auto k = static_cast<std::uint32_t>(id);
  const float r = kAtanHi[k] - ((t * (s1 + s2) - kAtanLo[k]) - t);
  return negative ? -r : r;
}

// atan2: fdlibm e_atan2f.c; quadrant from the signs, pi and pi/2 carried as hi + lo.
float atan2(float y, float x) {
  constexpr float kPiHi = 0x1.921fb6p+1f;     // float(pi)
  constexpr float kPiLo = -0x1.777a5cp-24f;   // pi - float(pi)
  constexpr float kPio2Hi = 0x1.921fb6p+0f;
  constexpr float kPio4Hi = 0x1.921fb6p-1f;
  constexpr float k3Pio4 = 0x1.2d97c8p+1f;    // float(3 pi / 4)
  const std::uint32_t hx = bits_of(x), hy = bits_of(y);
  const std::uint32_t ix = hx & kAbsMask, iy = hy & kAbsMask;
  if (ix > kInfBits || iy > kInfBits) return kQuietNaN();
  const std::uint32_t m = ((hy >> 31) & 1u) | ((hx >> 30) & 2u);  // bit 0: y < 0, bit 1: x < 0
  if (iy == 0u) {
    switch (m) {
      case 0u:
      case 1u: return y;  // atan2(+-0, +anything) = +-0
      case 2u: return kPiHi;
      default: return -kPiHi;
    }
  }
  if (ix == 0u) return (hy >> 31) != 0u ? -kPio2Hi : kPio2Hi;
  if (ix == kInfBits) {
    if (iy == kInfBits) {
      switch (m) {
        case 0u: return kPio4Hi;
        case 1u: return -kPio4Hi;
        case 2u: return k3Pio4;
        default: return -k3Pio4;
      }
    }
    switch (m) {
      case 0u: return 0.0f;
      case 1u: return -0.0f;
      case 2u: return kPiHi;
      default: return -kPiHi;
    }
  }
  if (iy == kInfBits) return (hy >> 31) != 0u ? -kPio2Hi : kPio2Hi;
  const int k = (static_cast<int>(iy) - static_cast<int>(ix)) >> 23;  // exponent difference
  float z = 0.0f;
  std::uint32_t quadrant = m;
  if (k > 26) {  // |y / x| > 2^26: pi/2 to within half an ULP
    z = kPio2Hi + 0.5f * kPiLo;
    quadrant &= 1u;
  } else if (k < -26 && (hx >> 31) != 0u) {  // |y| / x < -2^26: the result is +-pi
    z = 0.0f;
  } else {
    z = atan(abs(y / x));
  }
  switch (quadrant) {
    case 0u: return z;
    case 1u: return -z;
    case 2u: return kPiHi - (z - kPiLo);
    default: return (z - kPiLo) - kPiHi;
  }
}

// ---------------------------------------------------------------------------------------------------------------
// exp: fdlibm e_expf.c. x = k ln2 + r, |r| <= ln2 / 2, with ln2 = hi + lo (hi has 16 bits so k * hi is exact);
// exp(r) = 1 + 2r / (R(r) - r) through the Remez approximation c(r) of r (e^r + 1) / (e^r - 1); then scale by 2^k
// in the exponent bits.

float exp(float x) {
  constexpr float kLn2Hi = 0x1.62e4p-1f;
  constexpr float kLn2Lo = 0x1.7f7d1cp-20f;
  constexpr float kInvLn2 = 0x1.715476p+0f;
  constexpr float kUnderflow = -0x1.9fe36ap+6f;  // -103.97208: the greatest float whose exp rounds to 0
  constexpr float kP1 = 0xaaaaa8.0p-26f;
  constexpr float kP2 = -0xb55215.0p-32f;
  const std::uint32_t hx = bits_of(x);
  const std::uint32_t ix = hx & kAbsMask;
  const bool negative = (hx >> 31) != 0u;
  if (ix >= 0x42b17218u) {  // |x| >= 88.72284 (the least float whose exp exceeds FLT_MAX), or inf, or NaN
    if (ix > kInfBits) return kQuietNaN();
    if (ix == kInfBits) return negative ? 0.0f : x;
    if (!negative) return from_bits(kInfBits);  // overflow
    if (x <= kUnderflow) return 0.0f;           // underflow
  }
  float hi = x, lo = 0.0f;
  int k = 0;
  if (ix > 0x3eb17218u) {       // |x| > ln2 / 2
    if (ix < 0x3f851592u) {     // and |x| < 3 ln2 / 2: k = +-1
      hi = negative ? x + kLn2Hi : x - kLn2Hi;
      lo = negative ? -kLn2Lo : kLn2Lo;
      k = negative ? -1 : 1;
    } else {
      k = static_cast<int>(kInvLn2 * x + (negative ? -0.5f : 0.5f));
      const auto t = static_cast<float>(k);
      hi = x - t * kLn2Hi;
      lo = t * kLn2Lo;
    }
    x = hi - lo;
  } else if (ix < 0x39000000u) {  // |x| < 2^-14: exp(x) = 1 + x to within half an ULP
    return 1.0f + x;
  }
  const float t = x * x;
  const float c = x - t * (kP1 + t * kP2);
  if (k == 0) return 1.0f - ((x * c) / (c - 2.0f) - x);
  const float y = 1.0f - ((lo - (x * c) / (2.0f - c)) - hi);
  if (k >= -125) {
    if (k == 128) return y * 2.0f * 0x1p127f;
    return y * from_bits(static_cast<std::uint32_t>(127 + k) << 23);
  }
  // Subnormal result: scale in two steps so that only the last multiply rounds (gradual underflow).
  return y * from_bits(static_cast<std::uint32_t>(127 + k + 100) << 23) * 0x1p-100f;
}

// ---------------------------------------------------------------------------------------------------------------
// log: fdlibm e_logf.c. x = 2^k (1 + f) with sqrt(2)/2 <= 1 + f < sqrt(2) from the exponent bits, then
// log(1 + f) = 2s + s R(s^2) with s = f / (2 + f) = (m - 1) / (m + 1), R a minimax polynomial, ln2 = hi + lo.

float log(float x) {
  constexpr float kLn2Hi = 0x1.62e3p-1f;
  constexpr float kLn2Lo = 0x1.2fefa2p-17f;
  constexpr float kLg1 = 0xaaaaaa.0p-24f, kLg2 = 0xccce13.0p-25f, kLg3 = 0x91e9ee.0p-25f, kLg4 = 0xf89e26.0p-26f;
  std::uint32_t ix = bits_of(x);
  int k = 0;
  if (ix < 0x00800000u || (ix >> 31) != 0u) {  // zero, subnormal or negative
    if ((ix & kAbsMask) == 0u) return -from_bits(kInfBits);  // log(+-0) = -inf
    if ((ix >> 31) != 0u) return kQuietNaN();                 // log(x < 0) = NaN, also log(-NaN)
    k -= 25;                                                  // subnormal: scale by 2^25
    x *= 0x1p25f;
    ix = bits_of(x);
  }
  if (ix >= kInfBits) return ix == kInfBits ? x : kQuietNaN();  // log(inf) = inf, NaN propagates
  k += static_cast<int>(ix >> 23) - 127;
  ix &= 0x007fffffu;
  const std::uint32_t i = (ix + (0x95f64u << 3)) & 0x00800000u;  // 1 when the significand >= sqrt(2)
  x = from_bits(ix | (i ^ 0x3f800000u));                          // significand or its half
  k += static_cast<int>(i >> 23);
  const float f = x - 1.0f;
  const auto dk = static_cast<float>(k);
  if ((0x007fffffu & (0x8000u + ix)) < 0xc000u) {  // |f| < 2^-9: two terms of the series suffice
    if (f == 0.0f) return k == 0 ? 0.0f : dk * kLn2Hi + dk * kLn2Lo;
    const float r = f * f * (0.5f - 0.33333333333f * f);
    if (k == 0) return f - r;
    return dk * kLn2Hi - ((r - dk * kLn2Lo) - f);
  }
  const float s = f / (2.0f + f);
  const float z = s * s;
  const float w = z * z;
  const float t1 = w * (kLg2 + w * kLg4);
  const float t2 = z * (kLg1 + w * kLg3);
  const float r = t2 + t1;
  const bool far_from_one = static_cast<std::int32_t>((ix - (0x6147au << 3)) | ((0x6b851u << 3) - ix)) > 0;
  if (far_from_one) {
    const float hfsq = 0.5f * f * f;
    if (k == 0) return f - (hfsq - s * (hfsq + r));
    return dk * kLn2Hi - ((hfsq - (s * (hfsq + r) + dk * kLn2Lo)) - f);
  }
  if (k == 0) return f - s * (f - r);
  return dk * kLn2Hi - ((s * (f - r) - dk * kLn2Lo) - f);
}

// ---------------------------------------------------------------------------------------------------------------

float normalize_angle(float a) {
  constexpr float kPiLo = -0x1.777a5cp-24f;     // pi - float(pi)
  constexpr float kHalfPiLo = -0x1.777a5cp-25f;  // pi/2 - float(pi/2)
  const std::uint32_t ia = bits_of(a) & kAbsMask;
  if (ia >= kInfBits) return kQuietNaN();
  if (ia <= bits_of(kPi)) return a == -kPi ? kPi : a;  // already in [-pi, pi]: exact
  const Reduced red = reduce_pio2(from_bits(ia));
  // a = sign * (quadrant * pi/2 + r): fold the quadrant back in, with pi and pi/2 as hi + lo.
  const float r = a < 0.0f ? -red.hi : red.hi;
  const float lo = a < 0.0f ? -red.lo : red.lo;
  const std::uint32_t quadrant = a < 0.0f ? (4u - red.quadrant) & 3u : red.quadrant;
  float res = r;
  switch (quadrant) {
    case 0u: res = r; break;
    case 1u: res = kHalfPi + (r + (lo + kHalfPiLo)); break;
    case 3u: res = -kHalfPi + (r + (lo - kHalfPiLo)); break;
    default: res = r > 0.0f ? -kPi + (r + (lo - kPiLo)) : kPi + (r + (lo + kPiLo)); break;
  }
  return res <= -kPi ? kPi : res;
}

}  // namespace est::fmath
