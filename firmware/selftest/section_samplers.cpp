#include <cstdint>
#include <cstring>

#include "est/math/fmath.hpp"
#include "est/random/samplers.hpp"
#include "est/util/digest.hpp"
#include "selftest.hpp"

namespace est::selftest {
namespace {

float from_bits(std::uint32_t b) {
  float x = 0.0f;
  std::memcpy(&x, &b, sizeof x);
  return x;
}

void add_fmath(Digest& d, float x, float other) {
  d.add(fmath::sin(x));
  d.add(fmath::cos(x));
  float s = 0.0f, c = 0.0f;
  fmath::sincos(x, s, c);
  d.add(s);
  d.add(c);
  d.add(fmath::atan(x));
  d.add(fmath::atan2(x, other));
  d.add(fmath::exp(x));
  d.add(fmath::log(x));
  d.add(fmath::normalize_angle(x));
  d.add(fmath::sqrt(x));
}

}  // namespace

// Every sampler of est/random/samplers.hpp (table 5.4 and the bounded rejection sampler, both of its exits), both
// densities of table 5.2, and every est::fmath function over sweeps that cross all their paths: subnormals to
// FLT_MAX by bit pattern (Cody-Waite and Payne-Hanek reductions, each atan breakpoint, exp's overflow, subnormal
// and underflow ranges, log of subnormals), non-finite and negative inputs (canonical NaN bits), and the angles
// and exponents a filter actually sees.
std::uint64_t section_samplers() {
  Digest d;
  Rng rng(20261123u);
  for (int i = 0; i < 512; ++i) {
    d.add(sample_normal_box_muller(rng, 0.5f));
    d.add(sample_normal_sum12(rng, 0.5f));
    d.add(sample_triangular(rng, 0.5f));
    d.add(sample_normal(rng, 2.0f));
  }
  const auto beta34 = [](float x) { return x * x * (1.0f - x) * (1.0f - x) * (1.0f - x); };
  const auto truncated_normal = [](float x) { return prob_normal(x - 0.5f, 0.7f); };
  for (int i = 0; i < 256; ++i) {
    const RejectionSample a = sample_rejection(rng, beta34, 0.0f, 1.0f, 0.035f, 64u);
    const RejectionSample b = sample_rejection(rng, truncated_normal, -1.0f, 2.0f, 0.58f, 3u);  // gives up at times
    d.add(a.value);
    d.add_u32(a.tries | (a.ok ? 0x100u : 0u));
    d.add(b.value);
    d.add_u32(b.tries | (b.ok ? 0x100u : 0u));
  }
  const RejectionSample never = sample_rejection(rng, [](float) { return 0.0f; }, 0.0f, 1.0f, 1.0f, 10u);
  d.add_u32(never.tries | (never.ok ? 0x100u : 0u));
  d.add_u32(rng());
  for (int i = -80; i <= 80; ++i) {
    const float a = 0.05f * static_cast<float>(i);
    d.add(prob_normal(a, 1.3f));
    d.add(prob_triangular(a, 1.3f));
  }

  // All finite magnitudes, both signs, by bit pattern.
  for (std::uint32_t k = 0; k < 2048u; ++k) {
    const float x = from_bits(1u + k * 0xfeffu * 4u);
    add_fmath(d, x, from_bits(0x3f800000u + k * 0x1000u));
    add_fmath(d, -x, -from_bits(0x3f000000u + k * 0x2000u));
  }
  // The working ranges: angles, exponents down to the subnormals and past the overflow.
  for (int i = 0; i <= 2048; ++i) {
    const float t = static_cast<float>(i - 1024) * (1.0f / 64.0f);   // [-16, 16]
    const float e = static_cast<float>(i - 1100) * (1.0f / 10.0f);   // [-110, 94.8]
    add_fmath(d, t, 1.0f - t);
    d.add(fmath::exp(e));
  }
  const float specials[] = {0.0f, -0.0f, __builtin_inff(), -__builtin_inff(), __builtin_nanf(""), kPi, -kPi, kHalfPi};
  for (float special : specials) add_fmath(d, special, special);
  return d.value();
}

}  // namespace est::selftest
