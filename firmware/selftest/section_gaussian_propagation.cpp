#include "est/eigen.hpp"
#include "est/random/xoshiro128.hpp"
#include "est/util/digest.hpp"
#include "selftest.hpp"

namespace est::selftest {

// Linear-Gaussian prediction (Thrun table 3.1, lines 2-3) of a 6-state constant-velocity model, 1000 steps:
// exercises Eigen's fixed-size products in exactly the arithmetic the filters use.
std::uint64_t section_gaussian_propagation() {
  using Mat6 = Eigen::Matrix<float, 6, 6>;
  using Vec6 = Eigen::Matrix<float, 6, 1>;
  const float dt = 0.01f;
  Mat6 A = Mat6::Identity();
  for (int i = 0; i < 3; ++i) A(i, i + 3) = dt;
  Mat6 R = Mat6::Zero();
  for (int i = 0; i < 6; ++i) R(i, i) = (i < 3 ? 1e-4f : 1e-2f);
  Mat6 Sigma = Mat6::Identity();
  Vec6 mu = Vec6::Zero();
  Rng rng(42u);
  Digest d;
  for (int k = 0; k < 1000; ++k) {
    Vec6 u;
    for (int i = 0; i < 6; ++i) u(i) = rng.uniform(-0.01f, 0.01f);
    mu = A * mu + u;
    Sigma = A * Sigma * A.transpose() + R;
    if (k % 100 == 99) {
      d.add_matrix(mu);
      d.add_matrix(Sigma);
    }
  }
  return d.value();
}

}  // namespace est::selftest
