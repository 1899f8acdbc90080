#pragma once
// Low-variance (systematic) resampling, Thrun table 4.4: one random number, M equally spaced pointers.
// O(N_in + M) with both loops bounded; particle i is drawn floor(M w_i) or ceil(M w_i) times.
#include <cstdint>

#include "est/filter/particle_set.hpp"
#include "est/math/fmath.hpp"
#include "est/math/inline_exp.hpp"
#include "est/math/lanes.hpp"
#include "est/random/xoshiro128.hpp"

namespace est {

#if !defined(__arm__)
namespace low_variance_sampler_detail {

// The comb's walk over the exponentiated weights e, copying each drawn particle (and its mode when kMode).
template <bool kMode>
inline void comb_copy(const float* __restrict e, std::uint32_t count, std::uint32_t m, float r, float inv_m,
                      const float* __restrict ix, const float* __restrict iy, const float* __restrict it,
                      const std::uint8_t* __restrict im, float* __restrict ox, float* __restrict oy,
                      float* __restrict ot, std::uint8_t* __restrict om) {
  std::uint32_t i = 0;
  float c = e[0];
  for (std::uint32_t k = 0; k < m; ++k) {
    const float u = r + static_cast<float>(k) * inv_m;
    while (u > c && i + 1u < count) c += e[++i];
    ox[k] = ix[i];
    oy[k] = iy[i];
    ot[k] = it[i];
    if constexpr (kMode) om[k] = im[i];
  }
}

// The host's comb: the same pointers, sums and draws as the loop below (the same bits), with the weights' exps taken
// first, lanes::kLanes at a time (lanes::exp: imath::exp's bits), into out.log_w, which is free until the end (the
// weights 1/m are written after the comb). Needs in.count <= out.capacity.
inline std::uint32_t comb_host(ConstParticleSetView in, ParticleSetView out, std::uint32_t m, float r, float inv_m,
                               float log_uniform) {
  float* __restrict e = out.log_w;
  std::uint32_t j = 0;
  for (; j + lanes::kLanes <= in.count; j += lanes::kLanes) {
    lanes::F v;
    const lanes::I ok = lanes::exp(lanes::load(in.log_w + j), v);
    lanes::store(e + j, v);
    if (lanes::count(ok) == lanes::kLanes) continue;
    for (std::uint32_t l = 0; l < lanes::kLanes; ++l)
      if (ok[l] == 0) e[j + l] = imath::exp(in.log_w[j + l]);
  }
  for (; j < in.count; ++j) e[j] = imath::exp(in.log_w[j]);
  const float* __restrict ix = in.x;
  const float* __restrict iy = in.y;
  const float* __restrict it = in.theta;
  float* __restrict ox = out.x;
  float* __restrict oy = out.y;
  float* __restrict ot = out.theta;
  const std::uint8_t* __restrict im = in.mode;
  std::uint8_t* __restrict om = out.mode;
  if (im != nullptr && om != nullptr)
    comb_copy<true>(e, in.count, m, r, inv_m, ix, iy, it, im, ox, oy, ot, om);
  else
    comb_copy<false>(e, in.count, m, r, inv_m, ix, iy, it, im, ox, oy, ot, om);
  for (std::uint32_t k = 0; k < m; ++k) e[k] = log_uniform;
  return m;
}

}  // namespace low_variance_sampler_detail
#endif

// Draws m particles from `in` (normalized log weights) into `out` (capacity >= m), each with weight 1/m.
// Returns the number written (m clamped to out.capacity).
inline std::uint32_t low_variance_sampler(ConstParticleSetView in, ParticleSetView out, std::uint32_t m, Rng& rng) {
  if (m > out.capacity) m = out.capacity;
  if (m == 0u || in.count == 0u) return 0u;
  const float inv_m = 1.0f / static_cast<float>(m);
  const float r = rng.uniform() * inv_m;
  const float log_uniform = -fmath::log(static_cast<float>(m));
#if !defined(__arm__)
  if (in.count <= out.capacity) return low_variance_sampler_detail::comb_host(in, out, m, r, inv_m, log_uniform);
#endif
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
    if (in.mode != nullptr && out.mode != nullptr) out.mode[k] = in.mode[i];
    out.log_w[k] = log_uniform;
  }
  return m;
}

}  // namespace est
