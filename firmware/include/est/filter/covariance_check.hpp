#pragma once
// Positive-definiteness of a small fixed-size covariance by a bounded Cholesky factorization (n^3 / 6 steps), used
// where the state is small enough to afford it after every update (EKF localization, landmark initialization).
#include "est/eigen.hpp"
#include "est/math/fmath.hpp"

namespace est {

// True when A (symmetric, only the lower triangle read) is finite and positive definite.
template <int N>
bool is_positive_definite(const Eigen::Matrix<float, N, N>& A) {
  Eigen::Matrix<float, N, N> L = Eigen::Matrix<float, N, N>::Zero();
  for (int j = 0; j < N; ++j) {
    float d = A(j, j);
    for (int k = 0; k < j; ++k) d -= L(j, k) * L(j, k);
    if (!(d > 0.0f) || !fmath::isfinite(d)) return false;
    const float ljj = fmath::sqrt(d);
    L(j, j) = ljj;
    for (int i = j + 1; i < N; ++i) {
      float s = A(i, j);
      for (int k = 0; k < j; ++k) s -= L(i, k) * L(j, k);
      L(i, j) = s / ljj;
    }
  }
  return true;
}

}  // namespace est
