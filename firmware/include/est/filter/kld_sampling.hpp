#pragma once
// KLD-sampling (Fox 2003; Thrun table 8.4): samples are drawn one at a time and the histogram bins they fall in are
// counted; drawing stops once the number drawn n reaches n_chi(k), the count that keeps the Kullback-Leibler distance
// between the sample-based approximation and the true posterior below epsilon with probability 1 - delta for the k
// bins occupied so far (line 15), and n_min (line 17). KldStoppingRule is that rule: add() each sample in the order
// it is drawn (lines 11-16), done(n) is line 17's test. The drawing is the filter's (AugmentedMcl::resample): it
// draws i.i.d. from the weighted set, or from the recovery source with augmented MCL's injection probability, and
// counts the bins of every sample drawn, random ones included. Deterministic: bins are counted in a fixed-size
// table, no allocation; every loop is bounded by the table or by n_max.
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

  // True when the bin was empty (table 8.4, line 11), false when occupied or the table is saturated.
  bool insert(std::int32_t ix, std::int32_t iy, std::int32_t it) {
    if (saturated_) return false;
    const std::uint32_t key = hash(ix, iy, it);
    const std::uint64_t full = pack(ix, iy, it);
    std::uint32_t slot = key & (Capacity - 1u);
    for (std::uint32_t probe = 0; probe < Capacity; ++probe) {  // bounded by the table size
      if (stamp_[slot] != generation_) {
        stamp_[slot] = generation_;
        keys_[slot] = full;
        if (++count_ > Capacity / 2u) saturated_ = true;
        return true;
      }
      if (keys_[slot] == full) return false;
      slot = (slot + 1u) & (Capacity - 1u);
    }
    saturated_ = true;
    return false;
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

// Table 8.4's stopping rule over the samples drawn so far. start() is lines 2-4 (M = 0, k = 0, bins empty); add() is
// lines 11-16 for one sample (a new bin raises k and, for k > 1, the required count n_chi(k)); done(n) is line 17
// with n_max as the capacity's bound. A saturated bin table (more than Capacity/2 bins) asks for n_max.
template <std::uint32_t Capacity>
class KldStoppingRule {
 public:
  void start(const KldConfig& cfg, std::uint32_t n_max) {
    cfg_ = cfg;
    n_max_ = n_max;
    required_ = 1.0f;
    bins_.clear();
  }
  // A particle's mode (particle_set.hpp) is a dimension of the bins too: the same pose in two handle positions is
  // two hypotheses, each owed its samples. kUnknownMode (a filter without modes) leaves the pose's bin as it is.
  void add(float x, float y, float theta, std::uint8_t mode = kUnknownMode) {
    std::int32_t it = kld_bin(theta, cfg_.bin_theta);
    if (mode != kUnknownMode) it = it * 32 + static_cast<std::int32_t>(mode & 31u) + (1 << 20);
    if (bins_.insert(kld_bin(x, cfg_.bin_xy), kld_bin(y, cfg_.bin_xy), it) &&
        bins_.count() > 1u)
      required_ = kld_sample_count(bins_.count(), cfg_.epsilon, cfg_.z_one_minus_delta);
  }
  bool done(std::uint32_t n) const {
    if (n >= n_max_) return true;
    if (bins_.saturated()) return false;
    return n >= cfg_.n_min && static_cast<float>(n) >= required_;
  }
  std::uint32_t bins() const { return bins_.count(); }
  bool saturated() const { return bins_.saturated(); }
  float required() const { return required_; }

 private:
  KldConfig cfg_{};
  std::uint32_t n_max_ = 0;
  float required_ = 1.0f;
  BinCounter<Capacity> bins_;
};

}  // namespace est
