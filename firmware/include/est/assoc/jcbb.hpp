#pragma once
// Joint compatibility branch and bound (JCBB; Neira and Tardos, "Data association in stochastic mapping using the
// joint compatibility test", IEEE T-RA 2001) for the range-bearing sightings of one sensor frame against a known
// landmark map, with a Gaussian over the robot pose (x, y, theta).
//
// Every sighting i may pair with a landmark j (each landmark at most once per frame) or stay unpaired. A set of
// pairings is jointly compatible when the joint innovation's Mahalanobis distance passes the chi-square gate of its
// 2k dimensions (k pairings); individual nearest neighbour gates each pair alone, so two sightings can each pick a
// wrong landmark that a shifted pose would explain one at a time but not together. JCBB returns the jointly
// compatible assignment that pairs the most sightings, ties broken by the smaller joint distance.
//
// The joint distance is kept in information form: with the robot prior N(mu, P), and pairing i's linearization
// (H_i, nu_i, R_i),
//   d2 = nu^T (H P H^T + R)^-1 nu = c - b^T A^-1 b,  A = P^-1 + sum H_i^T R_i^-1 H_i,  b = sum H_i^T R_i^-1 nu_i,
//   c = sum nu_i^T R_i^-1 nu_i                          (the matrix inversion lemma),
// so extending a hypothesis by one pairing costs a 3 x 3 solve whatever the frame's size. d2 never decreases when a
// pairing is added (a Schur complement), which bounds the search: a branch is cut when even pairing every remaining
// sighting cannot beat the best count, or can only tie it with a distance already at or above the runner-up's (the
// second best assignment of as many pairings is kept too, for the caller's ambiguity test).
//
// Bounded: at most MaxSightings sightings per frame (more are refused: `too_many` in the result) and the
// MaxCandidates individually compatible landmarks of smallest distance per sighting (the rest are dropped and
// counted). The depth-first search has at most sum over levels of prod (candidates + 1) nodes, (MaxCandidates + 1)^
// MaxSightings in the worst case; it visits at most max_nodes of them (each one 3 x 3 solve) and, when that cap is
// hit, returns the best assignment found so far with node_cap_hit set. No heap: the storage is the object's.
#include <cstdint>

#include "est/eigen.hpp"
#include "est/filter/landmark_measurement.hpp"
#include "est/map/landmark_map.hpp"
#include "est/math/fmath.hpp"

namespace est {

// One sighting of a frame: range (m), bearing (rad, robot frame), and their standard deviations.
struct JcbbSighting {
  float range = 0.0f;
  float bearing = 0.0f;
  float sigma_range = 0.0f;
  float sigma_bearing = 0.0f;
};

struct JcbbParams {
  // The joint gate by the number k of pairings: the chi-square quantile of 2k degrees of freedom, index k - 1
  // (0.999 here, the EKF's individual gate of 13.816 for k = 1); beyond the table, its last entry grows by 3.2 per
  // pairing (about the quantile's slope there).
  static constexpr int kTable = 8;
  float joint_chi2[kTable] = {13.816f, 18.467f, 22.458f, 26.124f, 29.588f, 32.909f, 36.123f, 39.252f};
  float individual_chi2 = 13.816f;  // a pair beyond this alone is never a candidate
  std::uint32_t max_nodes = 4096;   // search nodes (hypotheses extended) per frame

  float joint_gate(int k) const {
    if (k <= 0) return 0.0f;
    if (k <= kTable) return joint_chi2[k - 1];
    return joint_chi2[kTable - 1] + 3.2f * static_cast<float>(k - kTable);
  }
};

template <int MaxSightings>
struct JcbbResult {
  std::int32_t landmark_of[static_cast<unsigned>(MaxSightings)];  // the map index paired with each sighting, or -1
  // The runner-up: the next best assignment with as many pairings (its joint distance the next smallest), for an
  // ambiguity test: a caller may fuse only the pairings both share when the two are close.
  std::int32_t runner_up_of[static_cast<unsigned>(MaxSightings)];
  bool has_runner_up = false;
  float runner_up_nis = 0.0f;
  std::int32_t paired = 0;
  float joint_nis = 0.0f;             // of the chosen assignment (0 when nothing is paired)
  std::uint32_t nodes = 0;            // search nodes visited
  std::uint32_t candidates_dropped = 0;  // individually compatible landmarks beyond MaxCandidates
  bool node_cap_hit = false;          // the search stopped at max_nodes: the result is the best found until then
  bool too_many = false;              // more sightings than MaxSightings: nothing associated
  bool ok = false;                    // false: bad input (covariance not positive definite, non-finite values)
};

namespace jcbb_detail {
// x = A^-1 b for a symmetric positive definite 3 x 3 A by Cholesky (A = L L^T); false if A is not.
inline bool spd_solve3(const Eigen::Matrix3f& A, const Eigen::Vector3f& b, Eigen::Vector3f& x) {
  float L[3][3] = {};
  for (int j = 0; j < 3; ++j) {
    float d = A(j, j);
    for (int k = 0; k < j; ++k) d -= L[j][k] * L[j][k];
    if (!(d > 0.0f) || !fmath::isfinite(d)) return false;
    L[j][j] = fmath::sqrt(d);
    for (int i = j + 1; i < 3; ++i) {
      float v = A(i, j);
      for (int k = 0; k < j; ++k) v -= L[i][k] * L[j][k];
      L[i][j] = v / L[j][j];
    }
  }
  float y[3];
  for (int i = 0; i < 3; ++i) {
    float v = b(i);
    for (int k = 0; k < i; ++k) v -= L[i][k] * y[k];
    y[i] = v / L[i][i];
  }
  for (int i = 2; i >= 0; --i) {
    float v = y[i];
    for (int k = i + 1; k < 3; ++k) v -= L[k][i] * x(k);
    x(i) = v / L[i][i];
  }
  return true;
}
}  // namespace jcbb_detail

template <int MaxSightings, int MaxCandidates>
class JointCompatibility {
  static_assert(MaxSightings >= 1 && MaxSightings <= 32, "a frame of 1 to 32 sightings");
  static_assert(MaxCandidates >= 1, "at least one candidate per sighting");

 public:
  using Result = JcbbResult<MaxSightings>;

  // mu, P: the robot's belief (x, y, theta); z[0..n): one frame's sightings; map: landmarks of at most 64 entries.
  Result associate(const Eigen::Vector3f& mu, const Eigen::Matrix3f& P, const JcbbSighting* z, int n,
                   const LandmarkMap& map, const JcbbParams& params) {
    Result out;
    for (int i = 0; i < MaxSightings; ++i) out.landmark_of[i] = out.runner_up_of[i] = -1;
    if (n < 0) return out;
    if (n > MaxSightings) {
      out.too_many = true;
      return out;
    }
    if (map.size() > 64) return out;
    for (int i = 0; i < 3; ++i)
      if (!fmath::isfinite(mu(i))) return out;
    Eigen::Matrix3f P_inv;
    for (int c = 0; c < 3; ++c) {
      Eigen::Vector3f col;
      if (!jcbb_detail::spd_solve3(P, Eigen::Vector3f::Unit(c), col)) return out;
      P_inv.col(c) = col;
    }
    P_inv = (0.5f * (P_inv + P_inv.transpose())).eval();
    n_ = n;
    for (int i = 0; i < n; ++i) out.candidates_dropped += candidates(mu, P, z[i], map, params, i);
    search(P_inv, params, out);
    out.ok = true;
    return out;
  }

 private:
  // What pairing sighting i with landmark j adds to the information-form sums.
  struct Pairing {
    Eigen::Matrix3f HtRH;
    Eigen::Vector3f HtRnu;
    float nuRnu = 0.0f;
    float d2 = 0.0f;  // individual Mahalanobis distance
    std::int32_t landmark = -1;
  };
  struct Level {  // the hypothesis after the levels above (the sums) and the branch being tried at this one
    Eigen::Matrix3f A;
    Eigen::Vector3f b;
    float c = 0.0f;
    float d2 = 0.0f;
    std::int32_t paired = 0;
    std::uint64_t used = 0;  // landmarks taken
    std::int32_t next = 0;   // the next branch: candidates 0..count-1, then count = unpaired
  };

  // Fills cand_[i] with the individually compatible landmarks of sighting i, smallest distance first; returns how
  // many were dropped for capacity.
  std::uint32_t candidates(const Eigen::Vector3f& mu, const Eigen::Matrix3f& P, const JcbbSighting& z,
                           const LandmarkMap& map, const JcbbParams& params, int i) {
    count_[i] = 0;
    if (!fmath::isfinite(z.range) || !fmath::isfinite(z.bearing) || !(z.sigma_range > 0.0f) ||
        !(z.sigma_bearing > 0.0f) || !fmath::isfinite(z.sigma_range) || !fmath::isfinite(z.sigma_bearing))
      return 0;
    const float rr = 1.0f / (z.sigma_range * z.sigma_range);
    const float rb = 1.0f / (z.sigma_bearing * z.sigma_bearing);
    std::uint32_t dropped = 0;
    for (std::int32_t j = 0; j < map.size(); ++j) {  // bounded by the map's 64
      const auto h = range_bearing_measurement<3>(mu, Eigen::Vector2f(map[j].x, map[j].y));
      if (!h.ok) continue;
      const Eigen::Vector2f nu(z.range - h.z(0), fmath::normalize_angle(z.bearing - h.z(1)));
      Eigen::Matrix2f S = h.H_robot * P * h.H_robot.transpose();
      S(0, 0) += z.sigma_range * z.sigma_range;
      S(1, 1) += z.sigma_bearing * z.sigma_bearing;
      const float det = S(0, 0) * S(1, 1) - S(0, 1) * S(1, 0);
      if (!(det > 0.0f)) continue;
      const float d2 = (nu(0) * S(1, 1) * nu(0) - 2.0f * nu(0) * S(0, 1) * nu(1) + nu(1) * S(0, 0) * nu(1)) / det;
      if (!fmath::isfinite(d2) || d2 > params.individual_chi2) continue;
      Pairing p;
      Eigen::Matrix<float, 3, 2> HtR = h.H_robot.transpose();
      HtR.col(0) *= rr;
      HtR.col(1) *= rb;
      p.HtRH = HtR * h.H_robot;
      p.HtRnu = HtR * nu;
      p.nuRnu = nu(0) * nu(0) * rr + nu(1) * nu(1) * rb;
      p.d2 = d2;
      p.landmark = j;
      // Insertion by distance into the bounded list; the farthest falls off when it is full.
      int k = count_[i] < MaxCandidates ? count_[i]++ : MaxCandidates;
      if (k == MaxCandidates) {
        ++dropped;
        if (!(d2 < cand_[i][MaxCandidates - 1].d2)) continue;
        k = MaxCandidates - 1;
      }
      while (k > 0 && cand_[i][k - 1].d2 > d2) {
        cand_[i][k] = cand_[i][k - 1];
        --k;
      }
      cand_[i][k] = p;
    }
    return dropped;
  }

  // Iterative depth-first branch and bound over levels 0..n-1 (explicit stack: no recursion).
  void search(const Eigen::Matrix3f& P_inv, const JcbbParams& params, Result& out) {
    std::int32_t best_paired = 0;
    float best_d2 = 0.0f;
    std::int32_t choice[kS];
    for (int i = 0; i < MaxSightings; ++i) choice[i] = -1;
    if (n_ == 0) return;
    stack_[0].A = P_inv;
    stack_[0].b.setZero();
    stack_[0].c = 0.0f;
    stack_[0].d2 = 0.0f;
    stack_[0].paired = 0;
    stack_[0].used = 0;
    stack_[0].next = 0;
    int level = 0;
    while (level >= 0) {
      Level& L = stack_[level];
      const int remaining = n_ - level;
      // Bound: the best this branch can still reach.
      const bool hopeless = L.paired + remaining < best_paired ||
                            (L.paired + remaining == best_paired && best_paired > 0 && out.has_runner_up &&
                             L.d2 >= out.runner_up_nis);
      if (hopeless || L.next > count_[level]) {
        --level;
        continue;
      }
      const std::int32_t branch = L.next++;
      if (out.nodes >= params.max_nodes) {
        out.node_cap_hit = true;
        break;
      }
      ++out.nodes;
      Level& N = stack_[level + 1 < MaxSightings ? level + 1 : level];
      Level next_level;
      Level& C = level + 1 < n_ ? N : next_level;  // the child (a leaf needs no stack slot)
      if (branch < count_[level]) {
        const Pairing& p = cand_[level][branch];
        if (L.used & (std::uint64_t{1} << p.landmark)) continue;
        C.A = L.A + p.HtRH;
        C.b = L.b + p.HtRnu;
        C.c = L.c + p.nuRnu;
        Eigen::Vector3f x;
        if (!jcbb_detail::spd_solve3(C.A, C.b, x)) continue;
        float d2 = C.c - C.b.dot(x);
        if (!fmath::isfinite(d2)) continue;
        if (d2 < L.d2) d2 = L.d2;  // rounding: the distance never decreases with a pairing
        C.paired = L.paired + 1;
        if (d2 > params.joint_gate(C.paired)) continue;
        C.d2 = d2;
        C.used = L.used | (std::uint64_t{1} << p.landmark);
        choice[level] = branch;
      } else {
        C.A = L.A;
        C.b = L.b;
        C.c = L.c;
        C.d2 = L.d2;
        C.paired = L.paired;
        C.used = L.used;
        choice[level] = -1;
      }
      C.next = 0;
      if (level + 1 < n_) {
        ++level;
        continue;
      }
      // A leaf: a complete, jointly compatible assignment.
      if (C.paired == 0) continue;
      if (C.paired > best_paired || (C.paired == best_paired && C.d2 < best_d2)) {
        if (C.paired == best_paired) {  // the best so far becomes the runner-up
          out.has_runner_up = true;
          out.runner_up_nis = best_d2;
          for (int i = 0; i < n_; ++i) out.runner_up_of[i] = out.landmark_of[i];
        } else {
          out.has_runner_up = false;
        }
        best_paired = C.paired;
        best_d2 = C.d2;
        for (int i = 0; i < n_; ++i) out.landmark_of[i] = choice[i] >= 0 ? cand_[i][choice[i]].landmark : -1;
      } else if (C.paired == best_paired && (!out.has_runner_up || C.d2 < out.runner_up_nis)) {
        out.has_runner_up = true;
        out.runner_up_nis = C.d2;
        for (int i = 0; i < n_; ++i) out.runner_up_of[i] = choice[i] >= 0 ? cand_[i][choice[i]].landmark : -1;
      }
    }
    out.paired = best_paired;
    out.joint_nis = best_d2;
  }

  static constexpr unsigned kS = static_cast<unsigned>(MaxSightings);
  Pairing cand_[kS][static_cast<unsigned>(MaxCandidates)];
  std::int32_t count_[kS] = {};
  Level stack_[kS];
  int n_ = 0;
};

}  // namespace est
