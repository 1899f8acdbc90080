#pragma once
// Samplers and densities of Probabilistic Robotics, table 5.2 and 5.4, with standard deviations as parameters.
// All draw from the firmware's own generator and math, so they give the same bits on every target.
#include <cstdint>

#include "est/math/fmath.hpp"
#include "est/random/xoshiro128.hpp"

namespace est {

// N(0, sigma^2) by Box-Muller; one of the pair is used, so each call takes exactly two draws. u1 >= 2^-24 bounds
// the output to |x| <= 5.77 sigma: the normal tail cut off there has probability 8e-9.
inline float sample_normal_box_muller(Rng& rng, float sigma) {
  const float u1 = rng.uniform_open_zero();
  const float u2 = rng.uniform();
  return sigma * fmath::sqrt(-2.0f * fmath::log(u1)) * fmath::cos(kTwoPi * u2);
}

// N(0, sigma^2) approximately, as the sum of 12 uniforms on [-sigma, sigma] halved (table 5.4, line 2);
// twelve draws, no transcendental, bounded to |x| <= 6 sigma.
inline float sample_normal_sum12(Rng& rng, float sigma) {
  float s = 0.0f;
  for (int i = 0; i < 12; ++i) s += rng.uniform(-sigma, sigma);
  return 0.5f * s;
}

// Triangular with standard deviation sigma, support |x| <= sqrt(6) sigma (table 5.4, line 3); two draws.
inline float sample_triangular(Rng& rng, float sigma) {
  constexpr float kHalfSqrt6 = 1.22474487139158904909f;
  return kHalfSqrt6 * (rng.uniform(-sigma, sigma) + rng.uniform(-sigma, sigma));
}

// The firmware's default normal sampler.
inline float sample_normal(Rng& rng, float sigma) { return sample_normal_box_muller(rng, sigma); }

// Density of N(0, sigma^2) at a (table 5.2, line 2), sigma > 0; 0 beyond |a| ~ 14 sigma where it underflows
// (for likelihood products use log_normal_density in est/math/normal.hpp).
inline float prob_normal(float a, float sigma) {
  constexpr float kInvSqrt2Pi = 0.39894228040143267794f;
  const float z = a / sigma;
  return kInvSqrt2Pi / sigma * fmath::exp(-0.5f * z * z);
}

// Density of the zero-mean triangular distribution with standard deviation sigma > 0 at a (table 5.2, line 4).
inline float prob_triangular(float a, float sigma) {
  constexpr float kSqrt6 = 2.44948974278317809820f;
  const float width = kSqrt6 * sigma;
  const float d = fmath::abs(a);
  return d >= width ? 0.0f : (width - d) / (width * width);
}

// Result of a bounded rejection sampler: ok is false when every try was rejected, and value is then unusable.
struct RejectionSample {
  float value;
  std::uint32_t tries;
  bool ok;
};

// Rejection sampling of a density f on [lo, hi] bounded by f_max, giving up after max_tries (the loop bound).
// The acceptance rate is (integral of f) / (f_max (hi - lo)); pick max_tries for the failure odds you can accept.
// f need not be normalized but must not exceed f_max on [lo, hi] (where it does, the samples are biased). Each try
// takes two draws (x, then the height), so a give-up advances the generator by exactly 2 max_tries draws.
template <typename Density>
RejectionSample sample_rejection(Rng& rng, const Density& f, float lo, float hi, float f_max,
                                 std::uint32_t max_tries) {
  for (std::uint32_t t = 1; t <= max_tries; ++t) {
    const float x = rng.uniform(lo, hi);
    const float y = rng.uniform(0.0f, f_max);
    if (y < f(x)) return {x, t, true};
  }
  return {0.0f, max_tries, false};
}

}  // namespace est
