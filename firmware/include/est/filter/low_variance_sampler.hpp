#pragma once
// Low-variance (systematic) resampling, Thrun table 4.4: one random number, M equally spaced pointers.
// O(N_in + M) with both loops bounded; particle i is drawn floor(M w_i) or ceil(M w_i) times.
#include <cstdint>

#include "est/filter/particle_set.hpp"
#include "est/math/fmath.hpp"
#include "est/math/inline_exp.hpp"
#include "est/random/xoshiro128.hpp"

namespace est {

// Draws m particles from `in` (normalized log weights) into `out` (capacity >= m), each with weight 1/m.
// Returns the number written (m clamped to out.capacity).
inline std::uint32_t low_variance_sampler(ConstParticleSetView in, ParticleSetView out, std::uint32_t m, Rng& rng) {
  if (m > out.capacity) m = out.capacity;
  if (m == 0u || in.count == 0u) return 0u;
  const float inv_m = 1.0f / static_cast<float>(m);
  const float r = rng.uniform() * inv_m;
  const float log_uniform = -fmath::log(static_cast<float>(m));
  std::uint32_t i = 0;
  float c = fmath::exp(in.log_w[0]);
  for (std::uint32_t k = 0; k < m; ++k) {
    const float u = r + static_cast<float>(k) * inv_m;
    // Rounding can leave the cumulative sum just short of 1: the last particle absorbs it.
    while (u > c && i + 1u < in.count) {
      ++i;
      c += imath::exp(in.log_w[i]);  // fmath::exp's bits, inline
    }
    out.x[k] = in.x[i];
    out.y[k] = in.y[i];
    out.theta[k] = in.theta[i];
    out.log_w[k] = log_uniform;
  }
  return m;
}

}  // namespace est
