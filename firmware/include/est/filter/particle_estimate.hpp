#pragma once
// Point estimates from a weighted particle set: weighted mean with the circular mean for heading, covariance with
// wrapped heading residuals, and the strongest cluster when the cloud is multi-modal.
#include <cstdint>

#include "est/eigen.hpp"
#include "est/filter/kld_sampling.hpp"
#include "est/filter/particle_set.hpp"
#include "est/geometry/pose2.hpp"
#include "est/math/fmath.hpp"

namespace est {

struct PoseEstimate {
  Pose2 mean;
  Eigen::Matrix3f covariance = Eigen::Matrix3f::Identity();
  float weight = 0.0f;            // total normalized weight of the particles used
  std::uint32_t particles = 0;    // how many particles contributed
};

namespace detail {

// Weighted mean and covariance of the particles for which `member(i)` is true.
template <typename Member>
PoseEstimate weighted_estimate(ConstParticleSetView s, const Member& member) {
  PoseEstimate e;
  float sw = 0.0f, sx = 0.0f, sy = 0.0f, ss = 0.0f, sc = 0.0f;
  std::uint32_t n = 0;
  for (std::uint32_t i = 0; i < s.count; ++i) {
    if (!member(i)) continue;
    const float w = fmath::exp(s.log_w[i]);
    float si = 0.0f, ci = 0.0f;
    fmath::sincos(s.theta[i], si, ci);
    sw += w;
    sx += w * s.x[i];
    sy += w * s.y[i];
    ss += w * si;
    sc += w * ci;
    ++n;
  }
  e.particles = n;
  e.weight = sw;
  if (!(sw > 0.0f)) return e;  // no weight: mean at the origin, unit covariance, weight 0 tells the caller
  e.mean = {sx / sw, sy / sw, fmath::atan2(ss, sc)};
  Eigen::Matrix3f c = Eigen::Matrix3f::Zero();
  for (std::uint32_t i = 0; i < s.count; ++i) {
    if (!member(i)) continue;
    const float w = fmath::exp(s.log_w[i]) / sw;
    const Eigen::Vector3f d(s.x[i] - e.mean.x, s.y[i] - e.mean.y, fmath::normalize_angle(s.theta[i] - e.mean.theta));
    c += w * (d * d.transpose());
  }
  e.covariance = c;
  return e;
}

}  // namespace detail

// Weighted mean of the whole set (Thrun 4.3.2's point estimate; the heading is the circular mean).
inline PoseEstimate weighted_mean(ConstParticleSetView s) {
  return detail::weighted_estimate(s, [](std::uint32_t) { return true; });
}

struct ClusterEstimate {
  PoseEstimate strongest;   // mean and covariance of the heaviest cluster
  PoseEstimate overall;     // the same over every particle
  bool multimodal = false;  // the strongest cluster holds less than `dominance` of the weight
};

// The strongest cluster's table: an open-addressing table of Slots cells of the coarse grid (a power of two).
// 13 bytes a slot: a filter keeps its own (AugmentedMcl) rather than putting 26 KiB on the stack at 2048 slots.
// mode_w: the cluster's weight per mode (by_mode below; modes 0..31 and the rest), here rather than on the step's
// stack, which the filters without modes would pay for too.
inline constexpr std::uint32_t kClusterModes = 33u;
template <std::uint32_t Slots>
struct ClusterTable {
  static_assert((Slots & (Slots - 1u)) == 0u, "Slots must be a power of two");
  std::int32_t cx[Slots];
  std::int32_t cy[Slots];
  float cw[Slots];
  bool taken[Slots];
  float mode_w[kClusterModes];
};

// Slots for sets of at most n particles: 2048, or fewer where that cannot change a result. A set of n particles
// fills at most n cells, and the table refuses cells only beyond Slots/2, so any Slots >= 2n gives the same
// clusters (a cell's weight is summed in particle order wherever its slot lies).
constexpr std::uint32_t cluster_slots(std::uint32_t n) {
  std::uint32_t slots = 16u;
  while (slots < 2048u && slots < 2u * n) slots *= 2u;
  return slots;
}

// The strongest cluster: particles are binned on a coarse grid of `cell` metres (the table's cells); the heaviest
// cell and its eight neighbours form the cluster. Two passes over the particles, each probe sequence bounded by
// Slots, and one over the table to clear it: bounded time, no heap. Cells beyond Slots/2 join no cluster seed.
// by_mode (a set whose particles carry modes, est/filter/particle_set.hpp): the cluster is further cut to its
// heaviest mode (modes from 32 up, and kUnknownMode, count as one), one more pass. Particles of one place and
// different modes are different hypotheses (the steered rangefinder's: the frame's heading differs by the handle's
// angle between them), and their mean would be neither.
template <std::uint32_t Slots>
ClusterEstimate strongest_cluster(ConstParticleSetView s, ClusterTable<Slots>& table, float cell = 1.0f,
                                  float dominance = 0.9f, bool by_mode = false) {
  ClusterEstimate out;
  out.overall = weighted_mean(s);
  std::int32_t* cx = table.cx;
  std::int32_t* cy = table.cy;
  float* cw = table.cw;
  bool* taken = table.taken;
  for (std::uint32_t j = 0; j < Slots; ++j) taken[j] = false;
  std::uint32_t used = 0;
  std::int32_t bx = 0, by = 0;
  float best = -1.0f;
  for (std::uint32_t i = 0; i < s.count; ++i) {
    const std::int32_t ix = kld_bin(s.x[i], cell), iy = kld_bin(s.y[i], cell);
    std::uint32_t slot = (static_cast<std::uint32_t>(ix) * 0x9e3779b1u ^ static_cast<std::uint32_t>(iy) * 0x85ebca77u);
    slot = (slot ^ (slot >> 15)) & (Slots - 1u);
    for (std::uint32_t probe = 0; probe < Slots; ++probe, slot = (slot + 1u) & (Slots - 1u)) {
      if (taken[slot] && cx[slot] == ix && cy[slot] == iy) break;
      if (!taken[slot]) {
        if (used >= Slots / 2u) {
          slot = Slots;  // table full enough: leave this particle out of the seeds
          break;
        }
        taken[slot] = true;
        cx[slot] = ix;
        cy[slot] = iy;
        cw[slot] = 0.0f;
        ++used;
        break;
      }
    }
    if (slot >= Slots) continue;
    cw[slot] += fmath::exp(s.log_w[i]);
    if (cw[slot] > best) {
      best = cw[slot];
      bx = ix;
      by = iy;
    }
  }
  if (used == 0u) {
    out.strongest = out.overall;
    return out;
  }
  const auto in_cluster = [&](std::uint32_t i) {
    const std::int32_t dx = kld_bin(s.x[i], cell) - bx, dy = kld_bin(s.y[i], cell) - by;
    return dx >= -1 && dx <= 1 && dy >= -1 && dy <= 1;
  };
  if (by_mode && s.mode != nullptr) {
    constexpr std::uint32_t kModes = kClusterModes;  // 0..31, and the rest
    const auto mode_of = [&](std::uint32_t i) { return s.mode[i] < kModes - 1u ? s.mode[i] : kModes - 1u; };
    float* mw = table.mode_w;
    for (std::uint32_t m = 0; m < kModes; ++m) mw[m] = 0.0f;
    for (std::uint32_t i = 0; i < s.count; ++i)
      if (in_cluster(i)) mw[mode_of(i)] += fmath::exp(s.log_w[i]);
    std::uint32_t bm = 0;
    for (std::uint32_t m = 1; m < kModes; ++m)
      if (mw[m] > mw[bm]) bm = m;
    out.strongest = detail::weighted_estimate(s, [&](std::uint32_t i) { return mode_of(i) == bm && in_cluster(i); });
  } else {
    out.strongest = detail::weighted_estimate(s, in_cluster);
  }
  out.multimodal = out.strongest.weight < dominance;
  return out;
}

// The same with a table on the stack (Slots x 13 bytes).
template <std::uint32_t Slots = 2048>
ClusterEstimate strongest_cluster(ConstParticleSetView s, float cell = 1.0f, float dominance = 0.9f,
                                  bool by_mode = false) {
  ClusterTable<Slots> table;
  return strongest_cluster(s, table, cell, dominance, by_mode);
}

}  // namespace est
