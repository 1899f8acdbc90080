#pragma once
// Standard normal draws in bulk for the batched particle-filter loops, by the inverse CDF: one 24-bit uniform per
// draw, its top 9 bits pick one of 512 equal-probability segments of (0, 1), the other 15 interpolate Phi^-1
// linearly inside it (est/random/normal_table.hpp); the two outer segments (probability 1/256 together, |x| > 2.886)
// take the tail formula of Abramowitz and Stegun 26.2.23 (error < 4.5e-4) with the firmware's own log and sqrt. No
// rejection: one uniform per value, bounded time, the same bits on every target (one multiply and one add per value
// in the body, integer indexing). About a quarter of Box-Muller's work per value on Cortex-M4F.
//
// Accuracy: inside a segment the linear interpolation moves a value by at most ~0.012 (the segments next to the
// tails, where Phi^-1 bends most) and by < 1e-5 for |x| < 1; each segment's probability is exact, so the CDF is off
// by less than 1e-4 anywhere. The uniforms have 24 bits: |x| <= 5.42 (kNormalBatchMax, tested). Distribution tested in
// tests/test_normal_batch.cpp (KS at 0.001, moments, the tails' mass).
#include <cstdint>

#include "est/math/fmath.hpp"
#include "est/math/inline_math.hpp"
#include "est/random/normal_table.hpp"
#include "est/random/xoshiro128.hpp"

namespace est {

// Every value fill_standard_normals gives is within +-kNormalBatchMax (the tail formula at p = 2^-25 gives 5.42).
inline constexpr float kNormalBatchMax = 5.5f;

namespace normal_batch_detail {

// Phi^-1 for p = (2 m + 1) 2^-25 in (0, 2^-9] (m < 2^15), negated: A&S 26.2.23.
inline float tail(std::uint32_t m) {
  const float p = static_cast<float>(2u * m + 1u) * 0x1p-25f;
  const float t = fmath::sqrt(-2.0f * imath::log_normal_positive(p));
  const float num = 2.515517f + t * (0.802853f + t * 0.010328f);
  const float den = 1.0f + t * (1.432788f + t * (0.189269f + t * 0.001308f));
  return t - num / den;
}

}  // namespace normal_batch_detail

// out[0 .. n-1] ~ N(0, 1), independent; draws n uniforms, in order (value i from the i-th).
inline void fill_standard_normals(Rng& rng, float* out, std::uint32_t n) {
  using normal_table::kFractionBits;
  using normal_table::kSegmentTable;
  constexpr std::uint32_t kLast = normal_table::kSegments - 1u;
  constexpr std::uint32_t kMask = (1u << kFractionBits) - 1u;
  Rng g = rng;  // a local copy stays in registers (the stores to out could otherwise alias it)
  for (std::uint32_t i = 0; i < n; ++i) {
    const std::uint32_t u = g.next() >> 8;  // 24 bits
    const std::uint32_t j = u >> kFractionBits;
    const std::uint32_t f = u & kMask;
    const normal_table::Segment seg = kSegmentTable[j];
    float x = seg.start + static_cast<float>(f) * seg.slope;
    if (j - 1u >= kLast - 1u) {  // j == 0 or j == 511: the tails, 1 draw in 256
      x = j == 0u ? -normal_batch_detail::tail(f) : normal_batch_detail::tail(kMask - f);
    }
    out[i] = x;
  }
  rng = g;
}

}  // namespace est
