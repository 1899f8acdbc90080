#include <catch2/catch.hpp>

#include <cmath>

#include "est/assoc/permutation_belief.hpp"
#include "est/random/samplers.hpp"

namespace {

// Three robots whose EKFs hold position estimates with covariance sigma_est^2 I; a field sensor measures each
// robot's position with noise sigma_z, and reports the three in a shuffled order (which robot is which is unknown).
struct Team3 {
  float truth[3][2] = {{0.0f, 0.0f}, {1.2f, 0.3f}, {0.4f, 1.1f}};
  float sigma_est = 0.3f;
  float sigma_z = 0.2f;
};

float log_gauss2(float dx, float dy, float var) {
  return -0.5f * (dx * dx + dy * dy) / var - est::fmath::log(2.0f * est::kPi * var);
}

}  // namespace

TEST_CASE("six hypotheses for three robots, the identity first, each a permutation", "[permutation_belief]") {
  est::PermutationBelief<3> b;
  REQUIRE(b.kHypotheses == 6);
  for (int h = 0; h < 6; ++h) {
    CHECK(b.probability(h) == Approx(1.0 / 6.0).epsilon(1e-5));
    int seen = 0;
    for (int k = 0; k < 3; ++k) seen |= 1 << b.robot_of(h, k);
    CHECK(seen == 7);
  }
  CHECK(b.robot_of(0, 0) == 0);
  CHECK(b.robot_of(0, 2) == 2);
  CHECK(b.robot_of(5, 0) == 2);
}

TEST_CASE("with 3 robots seen anonymously, the right assignment wins", "[permutation_belief]") {
  const Team3 t;
  est::Rng rng(21u);
  int wins = 0;
  constexpr int kTrials = 50;
  for (int trial = 0; trial < kTrials; ++trial) {
    // The filters' estimates of the robots: truth plus their own error.
    float est_pos[3][2];
    for (int i = 0; i < 3; ++i)
      for (int c = 0; c < 2; ++c) est_pos[i][c] = t.truth[i][c] + est::sample_normal(rng, t.sigma_est);
    const int order = static_cast<int>(rng.below(6u));  // the sensor's unknown order
    est::PermutationBelief<3> b;
    const float var = t.sigma_est * t.sigma_est + t.sigma_z * t.sigma_z;  // innovation covariance
    for (int step = 0; step < 10; ++step) {
      est::PermutationBelief<3>::LogLikelihoods L;
      for (int k = 0; k < 3; ++k) {
        const int who = b.robot_of(order, k);
        const float zx = t.truth[who][0] + est::sample_normal(rng, t.sigma_z);
        const float zy = t.truth[who][1] + est::sample_normal(rng, t.sigma_z);
        for (int i = 0; i < 3; ++i) L[k][i] = log_gauss2(zx - est_pos[i][0], zy - est_pos[i][1], var);
      }
      REQUIRE(b.update(L));
    }
    float total = 0.0f;
    for (int h = 0; h < 6; ++h) total += b.probability(h);
    CHECK(total == Approx(1.0f).epsilon(1e-4));
    wins += b.most_probable() == order ? 1 : 0;
  }
  // The estimates are off by 0.3 m per axis for robots ~1.2 m apart: one look is often wrong, ten rarely.
  WARN("right assignment most probable in " << wins << " of " << kTrials);
  CHECK(wins >= 47);
}

TEST_CASE("evidence piles up: the right hypothesis's probability grows to certainty", "[permutation_belief]") {
  est::PermutationBelief<3> b;
  // Measurement k is robot (k + 1) % 3: hypothesis with perm (1, 2, 0), which is index 3 in lexicographic order.
  int truth_h = -1;
  for (int h = 0; h < 6; ++h)
    if (b.robot_of(h, 0) == 1 && b.robot_of(h, 1) == 2 && b.robot_of(h, 2) == 0) truth_h = h;
  REQUIRE(truth_h == 3);
  est::PermutationBelief<3>::LogLikelihoods L;
  for (int k = 0; k < 3; ++k)
    for (int i = 0; i < 3; ++i) L[k][i] = (i == (k + 1) % 3) ? -1.0f : -3.0f;
  float last = b.probability(truth_h);
  for (int s = 0; s < 20; ++s) {
    REQUIRE(b.update(L));
    CHECK(b.probability(truth_h) >= last);
    last = b.probability(truth_h);
  }
  CHECK(last > 0.999f);
  // A non-finite likelihood is refused and changes nothing.
  L[0][0] = std::nanf("");
  CHECK_FALSE(b.update(L));
  CHECK(b.probability(truth_h) == last);
  // Partial view: one robot seen; only hypotheses disagreeing about it are moved.
  est::PermutationBelief<3> c;
  est::PermutationBelief<3>::LogLikelihoods one{};
  one[0][0] = 0.0f;
  one[0][1] = -50.0f;
  one[0][2] = -50.0f;
  REQUIRE(c.update(one, 1));
  CHECK(c.probability(0) + c.probability(1) == Approx(1.0f).epsilon(1e-5));  // the two with measurement 0 -> robot 0
}
