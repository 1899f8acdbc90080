#pragma once
// The EKF correction (Thrun table 3.3 lines 4-6, table 10.1 lines 17-19) for a measurement whose Jacobian H touches
// only a few blocks of a large state (one or two robots and at most one landmark in cooperative EKF-SLAM).
//
// Cost O(n^2 m) for n active states and an m-dimensional measurement, never O(n^3), and no dense m x n H:
//   P H^T     from the touched columns of P only                      O(n m w)
//   S         = H (P H^T) + Q from the touched rows of P H^T          O(m^2 w)
//   K         = (P H^T) S^-1                                          O(n m^2)
//   P+        = (I - K H) P (I - K H)^T + K Q K^T, the Joseph form, expanded with H P H^T = S - Q into
//             P - K (P H^T)^T - (P H^T) K^T + K S K^T                 O(n^2 m)
// The expansion is exact algebra, so P+ keeps the Joseph form's defining property: an error dK in the gain changes
// P+ only at second order (the first-order terms carry K S - P H^T = 0). P+ is computed on the upper triangle and
// mirrored (symmetric bit for bit), its diagonal is checked before anything is written (a measurement that would
// make a variance non-positive is refused, the state untouched), and floored afterwards. Every sum runs in a fixed
// order, so the result is the same bits on every target.
#include <cstdint>

#include "est/eigen.hpp"
#include "est/filter/correction_status.hpp"
#include "est/math/fmath.hpp"

namespace est {

// H as at most kMaxBlocks dense column blocks of width <= kMaxWidth at given state offsets; zero elsewhere.
template <int Mdim>
struct SparseJacobian {
  static constexpr int kMaxBlocks = 3;
  static constexpr int kMaxWidth = 3;
  int count = 0;
  int offset[kMaxBlocks] = {0, 0, 0};
  int width[kMaxBlocks] = {0, 0, 0};
  Eigen::Matrix<float, Mdim, kMaxWidth> block[kMaxBlocks];

  template <int W>
  void add(int state_offset, const Eigen::Matrix<float, Mdim, W>& h) {
    static_assert(W >= 1 && W <= kMaxWidth, "block wider than kMaxWidth");
    if (count >= kMaxBlocks) return;
    offset[count] = state_offset;
    width[count] = W;
    block[count].setZero();
    block[count].template leftCols<W>() = h;
    ++count;
  }
  bool is_finite() const {
    for (int b = 0; b < count; ++b)
      for (int c = 0; c < width[b]; ++c)
        for (int k = 0; k < Mdim; ++k)
          if (!fmath::isfinite(block[b](k, c))) return false;
    return true;
  }
};

// Covariance floor (a minimum variance per state entry) and the tolerance of the positivity check on P+'s diagonal.
struct CovarianceGuard {
  float variance_floor = 1.0e-9f;
  // A new variance below -negative_tolerance * (old variance) is an error beyond float rounding: refuse the update.
  // Between that and the floor it is rounding, and the floor restores it.
  float negative_tolerance = 1.0e-3f;
};

namespace detail {

template <int Mdim>
inline bool invert_spd(const Eigen::Matrix<float, Mdim, Mdim>& S, Eigen::Matrix<float, Mdim, Mdim>& S_inv) {
  static_assert(Mdim == 1 || Mdim == 2, "measurements of one or two dimensions");
  if constexpr (Mdim == 1) {
    if (!(S(0, 0) > 0.0f) || !fmath::isfinite(S(0, 0))) return false;
    S_inv(0, 0) = 1.0f / S(0, 0);
  } else {
    const float det = S(0, 0) * S(1, 1) - S(0, 1) * S(1, 0);
    if (!(S(0, 0) > 0.0f) || !(det > 0.0f) || !fmath::isfinite(det)) return false;
    const float inv_det = 1.0f / det;
    S_inv(0, 0) = S(1, 1) * inv_det;
    S_inv(1, 1) = S(0, 0) * inv_det;
    S_inv(0, 1) = -S(0, 1) * inv_det;
    S_inv(1, 0) = S_inv(0, 1);
  }
  return true;
}

}  // namespace detail

// One correction of (mu, P) over the first n entries of an N-state. `innovation` is z - h(mu), with any angle
// already wrapped; angle_mask marks the state entries to re-wrap to (-pi, pi] afterwards (headings), may be null.
// gate <= 0 disables gating. On refusal mu and P are left exactly as they were.
template <int N, int Mdim>
CorrectionResult sparse_joseph_update(Eigen::Matrix<float, N, 1>& mu, Eigen::Matrix<float, N, N>& P, int n,
                                      const SparseJacobian<Mdim>& H, const Eigen::Matrix<float, Mdim, 1>& innovation,
                                      const Eigen::Matrix<float, Mdim, Mdim>& Q, float gate,
                                      const CovarianceGuard& guard, const bool* angle_mask = nullptr) {
  CorrectionResult out;
  if (n <= 0 || n > N) return out;
  for (int b = 0; b < H.count; ++b)
    if (H.offset[b] < 0 || H.offset[b] + H.width[b] > n) return out;
  for (int k = 0; k < Mdim; ++k) {
    if (!fmath::isfinite(innovation(k))) return {CorrectionStatus::rejected_nonfinite, -1.0f};
    for (int l = 0; l < Mdim; ++l)
      if (!fmath::isfinite(Q(k, l))) return {CorrectionStatus::rejected_nonfinite, -1.0f};
  }
  if (!H.is_finite()) return {CorrectionStatus::rejected_nonfinite, -1.0f};

  // P H^T from the touched columns of P.
  Eigen::Matrix<float, N, Mdim> PHt;
  for (int r = 0; r < n; ++r) {
    for (int k = 0; k < Mdim; ++k) {
      float s = 0.0f;
      for (int b = 0; b < H.count; ++b)
        for (int c = 0; c < H.width[b]; ++c) s += P(r, H.offset[b] + c) * H.block[b](k, c);
      PHt(r, k) = s;
    }
  }
  // S = H P H^T + Q from the touched rows of P H^T, symmetrized.
  Eigen::Matrix<float, Mdim, Mdim> S;
  for (int k = 0; k < Mdim; ++k) {
    for (int l = 0; l < Mdim; ++l) {
      float s = 0.0f;
      for (int b = 0; b < H.count; ++b)
        for (int c = 0; c < H.width[b]; ++c) s += H.block[b](k, c) * PHt(H.offset[b] + c, l);
      S(k, l) = s + Q(k, l);
    }
  }
  for (int k = 0; k < Mdim; ++k)
    for (int l = k + 1; l < Mdim; ++l) S(k, l) = S(l, k) = 0.5f * (S(k, l) + S(l, k));
  Eigen::Matrix<float, Mdim, Mdim> S_inv;
  if (!detail::invert_spd<Mdim>(S, S_inv)) return {CorrectionStatus::rejected_not_pd, -1.0f};

  float nis = 0.0f;
  for (int k = 0; k < Mdim; ++k)
    for (int l = 0; l < Mdim; ++l) nis += innovation(k) * S_inv(k, l) * innovation(l);
  out.nis = nis;
  if (!fmath::isfinite(nis)) return {CorrectionStatus::rejected_nonfinite, -1.0f};
  if (gate > 0.0f && nis > gate) return {CorrectionStatus::rejected_gate, nis};

  // K = P H^T S^-1.
  Eigen::Matrix<float, N, Mdim> K;
  for (int r = 0; r < n; ++r)
    for (int k = 0; k < Mdim; ++k) {
      float s = 0.0f;
      for (int l = 0; l < Mdim; ++l) s += PHt(r, l) * S_inv(l, k);
      K(r, k) = s;
    }

  Eigen::Matrix<float, N, Mdim> KS;
  for (int r = 0; r < n; ++r)
    for (int k = 0; k < Mdim; ++k) {
      float s = 0.0f;
      for (int l = 0; l < Mdim; ++l) s += K(r, l) * S(l, k);
      KS(r, k) = s;
    }

  // Joseph-form entry (i, j): P_ij - K_i . PHt_j - PHt_i . K_j + (K S)_i . K_j.
  auto joseph = [&](int i, int j) {
    float a = 0.0f, b = 0.0f, c = 0.0f;
    for (int k = 0; k < Mdim; ++k) {
      a += K(i, k) * PHt(j, k);
      b += PHt(i, k) * K(j, k);
      c += KS(i, k) * K(j, k);
    }
    return ((P(i, j) - a) - b) + c;
  };

  // Check the new diagonal before writing anything.
  for (int i = 0; i < n; ++i) {
    const float d = joseph(i, i);
    if (!fmath::isfinite(d)) return {CorrectionStatus::rejected_nonfinite, nis};
    if (d < -guard.negative_tolerance * P(i, i)) return {CorrectionStatus::rejected_not_pd, nis};
  }
  for (int i = 0; i < n; ++i) {
    float dx = 0.0f;
    for (int k = 0; k < Mdim; ++k) dx += K(i, k) * innovation(k);
    if (!fmath::isfinite(dx)) return {CorrectionStatus::rejected_nonfinite, nis};
  }

  for (int i = 0; i < n; ++i) {
    float dx = 0.0f;
    for (int k = 0; k < Mdim; ++k) dx += K(i, k) * innovation(k);
    mu(i) += dx;
    if (angle_mask != nullptr && angle_mask[i]) mu(i) = fmath::normalize_angle(mu(i));
  }
  // Column j, rows 0..j: P(i, j) with i <= j is read only by the entry that overwrites it, so the update is in place.
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < j; ++i) {
      const float v = joseph(i, j);
      P(i, j) = v;
      P(j, i) = v;
    }
    const float d = joseph(j, j);
    P(j, j) = d > guard.variance_floor ? d : guard.variance_floor;
  }
  out.status = CorrectionStatus::accepted;
  return out;
}

}  // namespace est
