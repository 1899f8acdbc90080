#pragma once
// KLD-sampling (Fox 2003; Thrun table 8.4): the number of particles that keeps the Kullback-Leibler distance between
// the particle approximation and the true posterior below epsilon with probability 1 - delta, given the number k of
// histogram bins the particles occupy. Deterministic: bins are counted in a fixed-size table, no allocation.
#include <cstdint>

#include "est/filter/particle_set.hpp"
#include "est/math/fmath.hpp"

namespace est {

struct KldConfig {
  float epsilon = 0.05f;          // bound on the KL distance
  float z_one_minus_delta = 2.326f;  // upper standard normal quantile: 2.326 for delta = 0.01
  float bin_xy = 0.5f;            // bin size in x and y, m
  float bin_theta = 0.1745329f;   // bin size in heading, rad (10 deg)
  std::uint32_t n_min = 100;      // never fewer particles than this
};

// n = (k-1)/(2 eps) * (1 - 2/(9(k-1)) + sqrt(2/(9(k-1))) z)^3, the Wilson-Hilferty chi-square quantile (table 8.4, line 15).
inline float kld_sample_count(std::uint32_t k, float epsilon, float z) {
  if (k <= 1u) return 1.0f;
  const float km1 = static_cast<float>(k - 1u);
  const float a = 2.0f / (9.0f * km1);
  const float t = 1.0f - a + fmath::sqrt(a) * z;
  return km1 / (2.0f * epsilon) * t * t * t;
}

// Counts distinct occupied bins in a fixed open-addressing table of Capacity slots (a power of two). Once more than
// Capacity/2 bins are occupied the count saturates and reports `saturated`, which callers treat as "use N_max".
template <std::uint32_t Capacity>
class BinCounter {
  static_assert((Capacity & (Capacity - 1u)) == 0u && Capacity >= 16u, "capacity must be a power of two >= 16");

 public:
  void clear() {
    ++generation_;
    if (generation_ == 0u) {  // wrapped: stale stamps could match, so wipe them once every 2^32 clears
      for (std::uint32_t& s : stamp_) s = 0u;
      generation_ = 1u;
    }
    count_ = 0;
    saturated_ = false;
  }

  void insert(std::int32_t ix, std::int32_t iy, std::int32_t it) {
    if (saturated_) return;
    const std::uint32_t key = hash(ix, iy, it);
    const std::uint64_t full = pack(ix, iy, it);
    std::uint32_t slot = key & (Capacity - 1u);
    for (std::uint32_t probe = 0; probe < Capacity; ++probe) {  // bounded by the table size
      if (stamp_[slot] != generation_) {
        stamp_[slot] = generation_;
        keys_[slot] = full;
        if (++count_ > Capacity / 2u) saturated_ = true;
        return;
      }
      if (keys_[slot] == full) return;
      slot = (slot + 1u) & (Capacity - 1u);
    }
    saturated_ = true;
  }

  std::uint32_t count() const { return count_; }
  bool saturated() const { return saturated_; }

 private:
  static std::uint64_t pack(std::int32_t ix, std::int32_t iy, std::int32_t it) {
    return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(ix) & 0x1fffffu) << 42) |
           (static_cast<std::uint64_t>(static_cast<std::uint32_t>(iy) & 0x1fffffu) << 21) |
           (static_cast<std::uint64_t>(static_cast<std::uint32_t>(it) & 0x1fffffu));
  }
  static std::uint32_t hash(std::int32_t ix, std::int32_t iy, std::int32_t it) {
    std::uint32_t h = static_cast<std::uint32_t>(ix) * 0x9e3779b1u;
    h ^= static_cast<std::uint32_t>(iy) * 0x85ebca77u;
    h ^= static_cast<std::uint32_t>(it) * 0xc2b2ae3du;
    return h ^ (h >> 15);
  }

  std::uint64_t keys_[Capacity] = {};
  std::uint32_t stamp_[Capacity] = {};
  std::uint32_t generation_ = 1u;
  std::uint32_t count_ = 0;
  bool saturated_ = false;
};

inline std::int32_t kld_bin(float v, float size) {
  const float q = v / size;
  const float f = q < 0.0f ? q - 1.0f : q;  // floor for the negative side
  if (!(f > -1.0e6f)) return -1000000;
  if (!(f < 1.0e6f)) return 1000000;
  return static_cast<std::int32_t>(f);
}

// Number of particles KLD-sampling asks for given the particles' occupied bins, clamped to [n_min, n_max].
template <std::uint32_t Capacity>
std::uint32_t kld_particle_count(ConstParticleSetView set, const KldConfig& cfg, std::uint32_t n_max,
                                 BinCounter<Capacity>& bins) {
  bins.clear();
  for (std::uint32_t i = 0; i < set.count; ++i)
    bins.insert(kld_bin(set.x[i], cfg.bin_xy), kld_bin(set.y[i], cfg.bin_xy), kld_bin(set.theta[i], cfg.bin_theta));
  if (bins.saturated()) return n_max;
  const float n = kld_sample_count(bins.count(), cfg.epsilon, cfg.z_one_minus_delta);
  const float lo = static_cast<float>(cfg.n_min);
  const float hi = static_cast<float>(n_max);
  const float c = n < lo ? lo : (n > hi ? hi : n);
  const std::uint32_t count = static_cast<std::uint32_t>(c + 0.999f);
  return count > n_max ? n_max : count;
}

}  // namespace est
