#pragma once
// The EKF correction (Thrun table 3.3 lines 4-6, table 10.1 lines 17-19) for a measurement whose Jacobian H touches
// only a few blocks of a large state (one or two robots and at most one landmark in cooperative EKF-SLAM), in two
// forms of the covariance step. Both share, for n active states and an m-dimensional measurement (m = 1, 2), with no
// dense m x n H:
//   P H^T     from the touched columns of P only, one column of H at a time   O(n m w)
//   S         = H (P H^T) + Q from the touched rows of P H^T                  O(m^2 w)
// sparse_joseph_update: K = (P H^T) S^-1 and the Joseph form
//   P+        = (I - K H) P (I - K H)^T + K Q K^T, expanded with H P H^T = S - Q into
//             P - K (P H^T)^T - (P H^T) K^T + K S K^T                         O(n^2 m), 3m products per entry
//   The expansion is exact algebra, so P+ keeps the Joseph form's defining property: an error dK in the gain changes
//   P+ only at second order (the first-order terms carry K S - P H^T = 0). EKF localization (3 states) uses it.
// sparse_factored_update: S = L L^T (Cholesky, 2 x 2 at most), W = (P H^T) L^-T (n x m), and
//   P+        = P - K S K^T = P - W W^T,  mu+ = mu + W (L^-1 nu),  NIS = |L^-1 nu|^2   O(n^2 m), m products per entry
//   K S K^T = (P H^T) S^-1 (P H^T)^T is formed as a Gram matrix, symmetric by construction and never negative
//   (the subtraction is the only cancellation, as in the Joseph expansion's P - a - b + c). The gain is never formed,
//   so there is no gain error for the Joseph form to absorb: each entry of W carries two or three roundings, the
//   relative error of the terms the Joseph expansion rounds too (tests/test_sparse_joseph_update.cpp: the two forms
//   agree within 1.3e-6 of the largest entry after 200 updates). Cooperative EKF-SLAM (n up to 3 R + 2 M) uses it:
//   a third of the Joseph form's products on the n (n + 1) / 2 entries that dominate the cost (R = 2, M = 32 on
//   Cortex-M4F: 88 k -> 40 k instructions per range-bearing update).
// In both, P+ is computed on the upper triangle and mirrored (symmetric bit for bit), its diagonal is checked before
// anything is written (a measurement that would make a variance non-positive is refused, the state untouched), and
// floored afterwards. Every sum runs in a fixed order, so the result is the same bits on every target. Loops are
// bounded by n <= N and the at most kMaxBlocks x kMaxWidth columns of H.
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

// The checks both forms make before any arithmetic: false, with the refusal in *out, when the input is unusable.
template <int N, int Mdim>
inline bool usable_input(int n, const SparseJacobian<Mdim>& H, const Eigen::Matrix<float, Mdim, 1>& innovation,
                         const Eigen::Matrix<float, Mdim, Mdim>& Q, CorrectionResult* out) {
  if (n <= 0 || n > N) return false;
  for (int b = 0; b < H.count; ++b)
    if (H.offset[b] < 0 || H.offset[b] + H.width[b] > n) return false;
  for (int k = 0; k < Mdim; ++k) {
    if (!fmath::isfinite(innovation(k))) {
      *out = {CorrectionStatus::rejected_nonfinite, -1.0f};
      return false;
    }
    for (int l = 0; l < Mdim; ++l)
      if (!fmath::isfinite(Q(k, l))) {
        *out = {CorrectionStatus::rejected_nonfinite, -1.0f};
        return false;
      }
  }
  if (!H.is_finite()) {
    *out = {CorrectionStatus::rejected_nonfinite, -1.0f};
    return false;
  }
  return true;
}

// P H^T over the first n rows, one touched column of P at a time (each entry summed over H's columns in order), and
// S = H P H^T + Q from its touched rows, symmetrized.
template <int N, int Mdim>
inline void project(const Eigen::Matrix<float, N, N>& P, int n, const SparseJacobian<Mdim>& H,
                    const Eigen::Matrix<float, Mdim, Mdim>& Q, Eigen::Matrix<float, N, Mdim>& PHt,
                    Eigen::Matrix<float, Mdim, Mdim>& S) {
  for (int k = 0; k < Mdim; ++k)
    for (int r = 0; r < n; ++r) PHt(r, k) = 0.0f;
  for (int b = 0; b < H.count; ++b)
    for (int c = 0; c < H.width[b]; ++c) {
      const float* col = &P(0, H.offset[b] + c);
      float* out0 = &PHt(0, 0);
      float* out1 = &PHt(0, Mdim - 1);
      const float h0 = H.block[b](0, c);
      [[maybe_unused]] const float h1 = H.block[b](Mdim - 1, c);
      for (int r = 0; r < n; ++r) {
        out0[r] += col[r] * h0;
        if constexpr (Mdim == 2) out1[r] += col[r] * h1;
      }
    }
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
}

}  // namespace detail

// One correction of (mu, P) over the first n entries of an N-state, Joseph form. `innovation` is z - h(mu), with any
// angle already wrapped; angle_mask marks the state entries to re-wrap to (-pi, pi] afterwards (headings), may be
// null. gate <= 0 disables gating. On refusal mu and P are left exactly as they were.
template <int N, int Mdim>
CorrectionResult sparse_joseph_update(Eigen::Matrix<float, N, 1>& mu, Eigen::Matrix<float, N, N>& P, int n,
                                      const SparseJacobian<Mdim>& H, const Eigen::Matrix<float, Mdim, 1>& innovation,
                                      const Eigen::Matrix<float, Mdim, Mdim>& Q, float gate,
                                      const CovarianceGuard& guard, const bool* angle_mask = nullptr) {
  CorrectionResult out;
  if (!detail::usable_input<N, Mdim>(n, H, innovation, Q, &out)) return out;
  Eigen::Matrix<float, N, Mdim> PHt;
  Eigen::Matrix<float, Mdim, Mdim> S;
  detail::project<N, Mdim>(P, n, H, Q, PHt, S);
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

// One correction of (mu, P) over the first n entries of an N-state, factored form (P+ = P - W W^T, header comment);
// the arguments and refusals are sparse_joseph_update's. One temporary of n x m floats (W, in place of P H^T).
template <int N, int Mdim>
CorrectionResult sparse_factored_update(Eigen::Matrix<float, N, 1>& mu, Eigen::Matrix<float, N, N>& P, int n,
                                        const SparseJacobian<Mdim>& H,
                                        const Eigen::Matrix<float, Mdim, 1>& innovation,
                                        const Eigen::Matrix<float, Mdim, Mdim>& Q, float gate,
                                        const CovarianceGuard& guard, const bool* angle_mask = nullptr) {
  static_assert(Mdim == 1 || Mdim == 2, "measurements of one or two dimensions");
  CorrectionResult out;
  if (!detail::usable_input<N, Mdim>(n, H, innovation, Q, &out)) return out;
  Eigen::Matrix<float, N, Mdim> W;  // P H^T, then W = P H^T L^-T in place
  Eigen::Matrix<float, Mdim, Mdim> S;
  detail::project<N, Mdim>(P, n, H, Q, W, S);

  // S = L L^T with r_kk = 1 / L_kk; e = L^-1 nu, the whitened innovation: NIS = e^T e.
  float r0 = 0.0f, r1 = 0.0f, l10 = 0.0f;
  float e[2] = {0.0f, 0.0f};
  if (!(S(0, 0) > 0.0f) || !fmath::isfinite(S(0, 0))) return {CorrectionStatus::rejected_not_pd, -1.0f};
  r0 = 1.0f / fmath::sqrt(S(0, 0));
  e[0] = innovation(0) * r0;
  if constexpr (Mdim == 2) {
    l10 = S(1, 0) * r0;
    const float d1 = S(1, 1) - l10 * l10;
    if (!(d1 > 0.0f) || !fmath::isfinite(d1)) return {CorrectionStatus::rejected_not_pd, -1.0f};
    r1 = 1.0f / fmath::sqrt(d1);
    e[1] = (innovation(1) - l10 * e[0]) * r1;
  }
  float nis = e[0] * e[0];
  if constexpr (Mdim == 2) nis += e[1] * e[1];
  out.nis = nis;
  if (!fmath::isfinite(nis)) return {CorrectionStatus::rejected_nonfinite, -1.0f};
  if (gate > 0.0f && nis > gate) return {CorrectionStatus::rejected_gate, nis};

  // W row by row, the new diagonal and the mean's step checked before anything is written.
  for (int i = 0; i < n; ++i) {
    const float w0 = W(i, 0) * r0;
    W(i, 0) = w0;
    float q = w0 * w0;
    float dx = w0 * e[0];
    if constexpr (Mdim == 2) {
      const float w1 = (W(i, 1) - l10 * w0) * r1;
      W(i, 1) = w1;
      q += w1 * w1;
      dx += w1 * e[1];
    }
    const float d = P(i, i) - q;
    if (!fmath::isfinite(d) || !fmath::isfinite(dx)) return {CorrectionStatus::rejected_nonfinite, nis};
    if (d < -guard.negative_tolerance * P(i, i)) return {CorrectionStatus::rejected_not_pd, nis};
  }

  for (int i = 0; i < n; ++i) {
    float dx = W(i, 0) * e[0];
    if constexpr (Mdim == 2) dx += W(i, 1) * e[1];
    mu(i) += dx;
    if (angle_mask != nullptr && angle_mask[i]) mu(i) = fmath::normalize_angle(mu(i));
  }
  // Column j, rows 0..j-1, then the mirror row: each entry of the upper triangle is read once and written with its
  // mirror, so the update is in place.
  const float* w0 = &W(0, 0);
  const float* w1 = &W(0, Mdim - 1);
  for (int j = 0; j < n; ++j) {
    float* col = &P(0, j);
    float* row = &P(j, 0);
    const float a0 = w0[j];
    [[maybe_unused]] const float a1 = w1[j];
    auto entry = [&](int i) {
      float q = w0[i] * a0;
      if constexpr (Mdim == 2) q += w1[i] * a1;
      const float v = col[i] - q;
      col[i] = v;
      row[i * N] = v;
    };
    int i = 0;
    for (; i + 1 < j; i += 2) {  // two rows a turn: the loop's own instructions are a fifth of the work otherwise
      entry(i);
      entry(i + 1);
    }
    if (i < j) entry(i);
    float q = a0 * a0;
    if constexpr (Mdim == 2) q += a1 * a1;
    const float d = col[j] - q;
    col[j] = d > guard.variance_floor ? d : guard.variance_floor;
  }
  out.status = CorrectionStatus::accepted;
  return out;
}

}  // namespace est
