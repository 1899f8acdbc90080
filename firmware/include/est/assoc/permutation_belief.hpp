#pragma once
// Which robot is which, when external sensors see the team's robots without identifying them: a discrete Bayes
// filter (Thrun table 4.1 with a static state) over the N! assignments of anonymous measurements to robots.
// Hypothesis h maps measurement k to robot permutation(h)[k]; each update adds
//   log p(z | h) = sum_k log p(z_k | robot permutation(h)[k])
// (the measurements independent given the robots' states) and renormalizes. For N = 3 that is 6 hypotheses; the
// table of permutations grows as N!, so N is bounded at 5 (120): beyond that use gated_assignment (hungarian.hpp).
// Log weights are floored kLogFloor below the best, so a hypothesis pushed down by a fault can still recover, and
// nothing underflows to -inf.
#include <cstdint>

#include "est/math/fmath.hpp"

namespace est {

template <int N>
class PermutationBelief {
  static_assert(N >= 1 && N <= 5, "N! hypotheses: at most 5 robots (120); use gated_assignment beyond");

 public:
  static constexpr int factorial(int n) { return n <= 1 ? 1 : n * factorial(n - 1); }
  static constexpr int kHypotheses = factorial(N);
  static constexpr float kLogFloor = -60.0f;  // relative to the most probable hypothesis
  // log_lik[k][i] = log p(z_k | robot i)
  using LogLikelihoods = float[static_cast<unsigned>(N)][static_cast<unsigned>(N)];

  PermutationBelief() {
    std::uint8_t p[static_cast<unsigned>(N)];
    for (int k = 0; k < N; ++k) p[k] = static_cast<std::uint8_t>(k);
    for (int h = 0; h < kHypotheses; ++h) {  // lexicographic order, h = 0 the identity
      for (int k = 0; k < N; ++k) perm_[h][k] = p[k];
      next_permutation(p);
    }
    reset();
  }

  // Uniform: nothing known about who is who.
  void reset() {
    for (float& w : log_w_) w = -fmath::log(static_cast<float>(kHypotheses));
    updates_ = 0;
  }

  // One measurement set: log_lik[k][i] = log p(z_k | robot i), for the first `measured` measurements (<= N; fewer
  // when not every robot was seen). Returns false, and changes nothing, if a needed entry is NaN or +inf (-inf is an
  // impossible pairing and is allowed, floored like any other).
  bool update(const LogLikelihoods& log_lik, int measured = N) {
    if (measured < 0 || measured > N) return false;
    for (int k = 0; k < measured; ++k)
      for (int i = 0; i < N; ++i)
        if (log_lik[k][i] != log_lik[k][i] || log_lik[k][i] > 3.0e38f) return false;
    for (int h = 0; h < kHypotheses; ++h) {
      float l = 0.0f;
      for (int k = 0; k < measured; ++k) {
        const float lk = log_lik[k][perm_[h][k]];
        l += lk < -1.0e30f ? -1.0e30f : lk;
      }
      log_w_[h] += l;
    }
    normalize();
    ++updates_;
    return true;
  }

  float probability(int h) const { return fmath::exp(log_w_[h]); }
  float log_probability(int h) const { return log_w_[h]; }
  // The robot that measurement k belongs to under hypothesis h.
  int robot_of(int h, int k) const { return perm_[h][k]; }
  int most_probable() const {
    int best = 0;
    for (int h = 1; h < kHypotheses; ++h)
      if (log_w_[h] > log_w_[best]) best = h;
    return best;
  }
  std::uint32_t updates() const { return updates_; }

 private:
  static void next_permutation(std::uint8_t (&p)[static_cast<unsigned>(N)]) {
    int i = N - 2;
    while (i >= 0 && p[i] >= p[i + 1]) --i;
    if (i < 0) return;
    int j = N - 1;
    while (p[j] <= p[i]) --j;
    const std::uint8_t t = p[i];
    p[i] = p[j];
    p[j] = t;
    for (int a = i + 1, b = N - 1; a < b; ++a, --b) {
      const std::uint8_t u = p[a];
      p[a] = p[b];
      p[b] = u;
    }
  }

  // Log-sum-exp about the maximum, then the floor.
  void normalize() {
    float mx = log_w_[0];
    for (int h = 1; h < kHypotheses; ++h) mx = log_w_[h] > mx ? log_w_[h] : mx;
    float sum = 0.0f;
    for (int h = 0; h < kHypotheses; ++h) {
      float d = log_w_[h] - mx;
      if (d < kLogFloor) d = kLogFloor;
      log_w_[h] = d;
      sum += fmath::exp(d);
    }
    const float log_sum = fmath::log(sum);
    for (float& w : log_w_) w -= log_sum;
  }

  std::uint8_t perm_[static_cast<unsigned>(kHypotheses)][static_cast<unsigned>(N)] = {};
  float log_w_[static_cast<unsigned>(kHypotheses)] = {};
  std::uint32_t updates_ = 0;
};

}  // namespace est
