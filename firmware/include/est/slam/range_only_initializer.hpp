#pragma once
// Delayed initialization of range-only landmarks: one range fixes a landmark only to a circle, so observations are
// buffered until circles from robot positions spread in two directions intersect in one point, then the landmark is
// placed by least squares and enters the EKF-SLAM state (cf. Thrun ch. 10.3 on initializing features; the closed-form
// step is the classic linearized multilateration, refined by Gauss-Newton).
//
//   0. Buffering: a range taken within min_separation of a buffered position is not kept (it would crowd out the
//      spread the geometry needs); a full buffer drops its oldest observation.
//   1. Linear step: |m - p_k|^2 = r_k^2 minus its mean over k is linear in m:
//        2 (p_k - p_bar)^T (m - p_bar) = |p_k - p_bar|^2 - mean |p - p_bar|^2 - r_k^2 + mean r^2.
//      It is solved only when sum (p_k - p_bar)(p_k - p_bar)^T / K has smallest eigenvalue >= min_spread^2: with the
//      robot positions on one line the two circle intersections are mirror images and the landmark is ambiguous.
//   2. Gauss-Newton on sum w_k (|m - p_k| - r_k)^2, a fixed number of iterations, w_k = 1 / (var_r + u_k^T P_k u_k)
//      (range noise plus the robot's position uncertainty along the ray u_k).
//   3. Consistency: the weighted residual sum must pass chi-square(K - 2) at 99.9 %; else the oldest observation is
//      dropped (an outlier or a wrong id) and the landmark stays pending.
//   4. Covariance (J^T W J)^-1 times `inflation` (>= 1): the robot errors at the K observation times are correlated
//      with each other and with the current state, which the LS covariance ignores; the landmark enters the state
//      with this covariance and no cross-correlation, and the buffered ranges are not fused again (no double count).
// Bounded: Pending landmarks and Obs observations each are template capacities; iterations are fixed.
#include <cstdint>

#include "est/eigen.hpp"
#include "est/math/fmath.hpp"

namespace est {

struct RangeOnlyInitParams {
  std::int32_t min_observations = 4;  // >= 3; more makes the residual test meaningful
  float min_spread = 0.5f;            // m, the robot positions' smallest standard deviation over directions
  float min_separation = 0.25f;       // m: a range taken closer than this to a buffered one adds little and is skipped
  std::int32_t gauss_newton_iterations = 6;
  float inflation = 2.0f;             // covariance inflation for the ignored correlations (step 4)
};

enum class RangeOnlyInitStatus : std::uint8_t {
  pending = 0,       // observation kept; not enough geometry yet
  ready,             // mean and covariance available
  rejected_input,    // non-finite or non-positive range / noise
  rejected_capacity, // no free pending slot for a new landmark id
  inconsistent,      // the residual test failed; the oldest observation was dropped
};

struct RangeOnlyLandmark {
  Eigen::Vector2f mean = Eigen::Vector2f::Zero();
  Eigen::Matrix2f covariance = Eigen::Matrix2f::Identity();
};

template <int Pending, int Obs>
class RangeOnlyInitializer {
  static_assert(Pending >= 1 && Obs >= 3, "at least one pending landmark and three observations");

 public:
  explicit RangeOnlyInitializer(const RangeOnlyInitParams& p = RangeOnlyInitParams{}) : params_(p) {}

  // Buffers one range from a robot at position p (covariance P_p) to landmark id; when the landmark becomes
  // determined, returns ready and fills *out, and frees the slot. A full buffer drops its oldest observation.
  RangeOnlyInitStatus add(std::int32_t id, const Eigen::Vector2f& p, const Eigen::Matrix2f& P_p, float range,
                          float var_range, RangeOnlyLandmark* out) {
    if (!fmath::isfinite(range) || !fmath::isfinite(var_range) || !(range > 0.0f) || !(var_range > 0.0f) ||
        !fmath::isfinite(p(0)) || !fmath::isfinite(p(1)) || !P_p.allFinite())
      return RangeOnlyInitStatus::rejected_input;
    int s = find(id);
    if (s < 0) {
      for (int k = 0; k < Pending; ++k)
        if (!slot_[k].used) {
          s = k;
          slot_[k] = Slot{};
          slot_[k].used = true;
          slot_[k].id = id;
          break;
        }
      if (s < 0) return RangeOnlyInitStatus::rejected_capacity;
    }
    Slot& sl = slot_[s];
    for (int k = 0; k < sl.count; ++k)
      if ((sl.obs[k].p - p).squaredNorm() < params_.min_separation * params_.min_separation)
        return RangeOnlyInitStatus::pending;
    if (sl.count == Obs) drop_oldest(sl);
    sl.obs[sl.count++] = Observation{p, P_p, range, var_range};
    if (sl.count < params_.min_observations || sl.count < 3) return RangeOnlyInitStatus::pending;
    const RangeOnlyInitStatus st = solve(sl, out);
    if (st == RangeOnlyInitStatus::ready) sl.used = false;
    if (st == RangeOnlyInitStatus::inconsistent) drop_oldest(sl);
    return st;
  }

  std::int32_t observations(std::int32_t id) const {
    const int s = find(id);
    return s < 0 ? 0 : slot_[s].count;
  }
  void forget(std::int32_t id) {
    const int s = find(id);
    if (s >= 0) slot_[s].used = false;
  }
  void clear() {
    for (Slot& s : slot_) s.used = false;
  }
  const RangeOnlyInitParams& params() const { return params_; }

 private:
  struct Observation {
    Eigen::Vector2f p = Eigen::Vector2f::Zero();
    Eigen::Matrix2f P_p = Eigen::Matrix2f::Zero();
    float range = 0.0f;
    float var_range = 0.0f;
  };
  struct Slot {
    bool used = false;
    std::int32_t id = 0;
    std::int32_t count = 0;
    Observation obs[static_cast<unsigned>(Obs)];
  };

  int find(std::int32_t id) const {
    for (int k = 0; k < Pending; ++k)
      if (slot_[k].used && slot_[k].id == id) return k;
    return -1;
  }
  static void drop_oldest(Slot& s) {
    for (int k = 1; k < s.count; ++k) s.obs[k - 1] = s.obs[k];
    if (s.count > 0) --s.count;
  }

  // Upper 99.9 % quantile of chi-square with k degrees of freedom (Wilson-Hilferty, z = 3.09; within 2 % for k >= 1).
  static float chi2_999(int k) {
    const float kf = static_cast<float>(k < 1 ? 1 : k);
    const float a = 2.0f / (9.0f * kf);
    const float t = 1.0f - a + 3.0902f * fmath::sqrt(a);
    return kf * t * t * t;
  }

  static Eigen::Matrix2f inverse2(const Eigen::Matrix2f& A) {
    const float inv_det = 1.0f / (A(0, 0) * A(1, 1) - A(0, 1) * A(1, 0));
    Eigen::Matrix2f B;
    B << A(1, 1) * inv_det, -A(0, 1) * inv_det, -A(1, 0) * inv_det, A(0, 0) * inv_det;
    return B;
  }

  RangeOnlyInitStatus solve(const Slot& s, RangeOnlyLandmark* out) const {
    const int K = s.count;
    const float inv_k = 1.0f / static_cast<float>(K);
    Eigen::Vector2f pbar = Eigen::Vector2f::Zero();
    for (int k = 0; k < K; ++k) pbar += s.obs[k].p;
    pbar *= inv_k;
    float mean_q2 = 0.0f, mean_r2 = 0.0f;
    Eigen::Matrix2f spread = Eigen::Matrix2f::Zero();
    for (int k = 0; k < K; ++k) {
      const Eigen::Vector2f q = s.obs[k].p - pbar;
      mean_q2 += q.squaredNorm();
      mean_r2 += s.obs[k].range * s.obs[k].range;
      spread += q * q.transpose();
    }
    mean_q2 *= inv_k;
    mean_r2 *= inv_k;
    spread *= inv_k;
    // Smallest eigenvalue of the 2x2 symmetric spread.
    const float tr = spread(0, 0) + spread(1, 1);
    const float det = spread(0, 0) * spread(1, 1) - spread(0, 1) * spread(1, 0);
    const float disc = fmath::sqrt(fmath::abs(0.25f * tr * tr - det));
    const float lambda_min = 0.5f * tr - disc;
    if (!(lambda_min >= params_.min_spread * params_.min_spread)) return RangeOnlyInitStatus::pending;

    // Step 1: normal equations of the linear system, in coordinates about pbar.
    Eigen::Matrix2f AtA = Eigen::Matrix2f::Zero();
    Eigen::Vector2f Atb = Eigen::Vector2f::Zero();
    for (int k = 0; k < K; ++k) {
      const Eigen::Vector2f q = s.obs[k].p - pbar;
      const float b = q.squaredNorm() - mean_q2 - s.obs[k].range * s.obs[k].range + mean_r2;
      AtA += 4.0f * q * q.transpose();
      Atb += 2.0f * q * b;
    }
    Eigen::Vector2f m = pbar + inverse2(AtA) * Atb;

    // Step 2: Gauss-Newton on the weighted range residuals.
    Eigen::Matrix2f JtWJ = Eigen::Matrix2f::Identity();
    float chi2 = 0.0f;
    for (int it = 0; it <= params_.gauss_newton_iterations; ++it) {
      JtWJ.setZero();
      Eigen::Vector2f JtWr = Eigen::Vector2f::Zero();
      chi2 = 0.0f;
      for (int k = 0; k < K; ++k) {
        const Eigen::Vector2f d = m - s.obs[k].p;
        const float r = fmath::sqrt(d.squaredNorm());
        if (!(r > 1.0e-4f)) return RangeOnlyInitStatus::pending;
        const Eigen::Vector2f u = d / r;
        const float w = 1.0f / (s.obs[k].var_range + u.dot(s.obs[k].P_p * u));
        const float res = s.obs[k].range - r;
        JtWJ += w * u * u.transpose();
        JtWr += w * res * u;
        chi2 += w * res * res;
      }
      const float dj = JtWJ(0, 0) * JtWJ(1, 1) - JtWJ(0, 1) * JtWJ(1, 0);
      if (!(dj > 0.0f)) return RangeOnlyInitStatus::pending;
      if (it == params_.gauss_newton_iterations) break;  // the last pass only evaluates J and the residual at m
      m += inverse2(JtWJ) * JtWr;
    }
    if (!m.allFinite()) return RangeOnlyInitStatus::pending;
    if (chi2 > chi2_999(K - 2)) return RangeOnlyInitStatus::inconsistent;
    Eigen::Matrix2f C = inverse2(JtWJ) * (params_.inflation < 1.0f ? 1.0f : params_.inflation);
    C = (0.5f * (C + C.transpose())).eval();
    out->mean = m;
    out->covariance = C;
    return RangeOnlyInitStatus::ready;
  }

  RangeOnlyInitParams params_;
  Slot slot_[static_cast<unsigned>(Pending)];
};

}  // namespace est
