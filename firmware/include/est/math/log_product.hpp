#pragma once
// log of a product of many positive factors, kept as the product itself: m 2^e with m in [1, 2) renormalized after
// every factor (exponent bits moved into an integer, exact), so there is no underflow and one log at the end instead
// of one per factor. Table 6.1 multiplies the beams' densities (q = q * p); this is that product, taken to log space
// once. Each factor is clamped to [1e-30, 1e30] (NaN to 1e-30), the floor log(1e-30) per factor of
// kBeamLogDensityFloor.
//
// Error against the exact sum of log factors: each multiplication rounds m by at most 2^-24 relative, so
// |log() - sum log d_k| <= n 2^-24 (1 + 2^-23) + 2 ULP of the result (fmath::log of m, and the assembly with
// e ln2 split in a hi part exact for |e| < 2^16 and a lo part). For n = 360 factors: <= 2.2e-5 + 2 ULP, less than
// a float sum of n per-factor logs, whose rounding grows with the partial sums (tests/test_log_product.cpp).
// Cost per factor: 1 multiplication and 4 integer operations; float and integer ops only, the same bits on every
// target.
#include <cstdint>
#include <cstring>

#include "est/math/fmath.hpp"

namespace est {

class LogProduct {
 public:
  static constexpr float kFactorMin = 1e-30f;
  static constexpr float kFactorMax = 1e30f;

  void mul(float d) {
    d = d > kFactorMin ? d : kFactorMin;  // also NaN
    d = d < kFactorMax ? d : kFactorMax;
    // m in [1, 2) and d in [2^-100, 2^100]: m d is a normal float, so its exponent field is the true exponent.
    const float p = m_ * d;
    std::uint32_t bits = 0;
    std::memcpy(&bits, &p, sizeof bits);
    e_ += static_cast<std::int32_t>(bits >> 23) - 127;
    bits = (bits & 0x007fffffu) | 0x3f800000u;
    std::memcpy(&m_, &bits, sizeof m_);
  }

  // log of the product: e ln2 + log m.
  float log() const {
    constexpr float kLn2Hi = 0x1.62p-1f;  // 8 significant bits: e kLn2Hi is exact for |e| < 2^16
    constexpr float kLn2Lo = 0x1.c85fep-10f;  // ln2 - kLn2Hi, rounded to float
    const float e = static_cast<float>(e_);
    return e * kLn2Hi + (e * kLn2Lo + fmath::log(m_));
  }

  std::int32_t exponent() const { return e_; }
  float mantissa() const { return m_; }

 private:
  float m_ = 1.0f;
  std::int32_t e_ = 0;
};

}  // namespace est
