#include <catch2/catch.hpp>
#include <cmath>

#include "est/filter/log_weights.hpp"
#include "est/filter/particle_estimate.hpp"
#include "est/random/samplers.hpp"

namespace {
constexpr double kPi = 3.14159265358979323846;
}

TEST_CASE("heading mean is circular: particles around +-pi average to pi, not 0", "[estimate]") {
  static est::ParticleSet<100> s;
  s.set_count(100);
  auto v = s.view();
  for (std::uint32_t i = 0; i < 100; ++i) {
    v.x[i] = 1.0f;
    v.y[i] = 2.0f;
    v.theta[i] = (i % 2 == 0) ? 3.1f : -3.1f;  // 0.0416 rad either side of pi
    v.log_w[i] = 0.0f;
  }
  est::normalize_log_weights(v.log_w, 100u);
  const auto e = est::weighted_mean(s.view());
  CHECK(std::abs(std::abs(static_cast<double>(e.mean.theta)) - kPi) < 1e-5);
  CHECK(e.mean.x == Approx(1.0f));
  CHECK(e.mean.y == Approx(2.0f));
  // Heading variance from wrapped residuals: (pi - 3.1)^2, not 3.1^2.
  CHECK(e.covariance(2, 2) == Approx((kPi - 3.1) * (kPi - 3.1)).epsilon(1e-3));
  CHECK(e.weight == Approx(1.0f).epsilon(1e-5));
}

TEST_CASE("weighted mean and covariance match the analytic Gaussian they were drawn from", "[estimate]") {
  static est::ParticleSet<20000> s;
  s.set_count(20000);
  auto v = s.view();
  est::Rng rng(4u);
  for (std::uint32_t i = 0; i < v.count; ++i) {
    v.x[i] = 3.0f + est::sample_normal(rng, 0.5f);
    v.y[i] = -1.0f + est::sample_normal(rng, 0.2f);
    v.theta[i] = 0.3f + est::sample_normal(rng, 0.1f);
    v.log_w[i] = 0.0f;
  }
  est::normalize_log_weights(v.log_w, v.count);
  const auto e = est::weighted_mean(s.view());
  // 5 standard errors of the mean (sigma / sqrt(20000)) and ~5 % on variances (s.e. of a variance is sqrt(2/n)).
  CHECK(e.mean.x == Approx(3.0f).margin(5 * 0.5 / std::sqrt(20000.0)));
  CHECK(e.mean.y == Approx(-1.0f).margin(5 * 0.2 / std::sqrt(20000.0)));
  CHECK(e.mean.theta == Approx(0.3f).margin(5 * 0.1 / std::sqrt(20000.0)));
  CHECK(e.covariance(0, 0) == Approx(0.25f).epsilon(0.05));
  CHECK(e.covariance(1, 1) == Approx(0.04f).epsilon(0.05));
  CHECK(e.covariance(2, 2) == Approx(0.01f).epsilon(0.05));
  CHECK(std::abs(e.covariance(0, 1)) < 0.01f);
}

TEST_CASE("strongest cluster picks the heavier of two modes and flags the cloud multimodal", "[estimate]") {
  static est::ParticleSet<2000> s;
  s.set_count(2000);
  auto v = s.view();
  est::Rng rng(9u);
  for (std::uint32_t i = 0; i < v.count; ++i) {
    const bool heavy = i < 1200;  // 60 % of the particles, equal weights
    v.x[i] = (heavy ? 5.0f : -5.0f) + est::sample_normal(rng, 0.1f);
    v.y[i] = (heavy ? 2.0f : 8.0f) + est::sample_normal(rng, 0.1f);
    v.theta[i] = heavy ? 1.0f : -2.0f;
    v.log_w[i] = 0.0f;
  }
  est::normalize_log_weights(v.log_w, v.count);
  const auto c = est::strongest_cluster(s.view());
  CHECK(c.multimodal);
  CHECK(c.strongest.mean.x == Approx(5.0f).margin(0.05));
  CHECK(c.strongest.mean.y == Approx(2.0f).margin(0.05));
  CHECK(c.strongest.mean.theta == Approx(1.0f).margin(1e-4));
  CHECK(c.strongest.weight == Approx(0.6f).epsilon(1e-3));
  // The overall mean sits between the modes, where no particle is: why the cluster estimate exists.
  CHECK(c.overall.mean.x == Approx(1.0f).margin(0.05));
}

TEST_CASE("a set with no weight gives a finite estimate with zero weight", "[estimate]") {
  static est::ParticleSet<4> s;
  s.set_count(4);
  auto v = s.view();
  for (std::uint32_t i = 0; i < 4; ++i) {
    v.x[i] = v.y[i] = v.theta[i] = 0.0f;
    v.log_w[i] = est::kLogZero;
  }
  const auto e = est::weighted_mean(s.view());
  CHECK(e.weight == 0.0f);
  CHECK(e.mean.is_finite());
  CHECK(e.covariance.allFinite());
}

TEST_CASE("by mode, the strongest cluster is cut to its heaviest mode: one place, two headings, not their mean",
          "[estimate]") {
  // 70 particles at heading 0.2 with mode 3 and 30 at heading 0.2 - 24 deg with mode 4, all at one place: the
  // steered rangefinder's two hypotheses of one sensor pose. By place alone the mean heading lies between them.
  static est::ParticleSet<100> s;
  s.set_count(100);
  auto v = s.view();
  for (std::uint32_t i = 0; i < 100; ++i) {
    const bool major = i < 70;
    v.x[i] = 3.0f + 0.001f * static_cast<float>(i % 7);
    v.y[i] = 4.0f;
    v.theta[i] = major ? 0.2f : 0.2f - 0.4189f;
    v.mode[i] = major ? 3u : 4u;
    v.log_w[i] = 0.0f;
  }
  est::normalize_log_weights(v.log_w, 100u);
  const auto mixed = est::strongest_cluster(s.view());
  CHECK(std::abs(static_cast<double>(mixed.strongest.mean.theta) - 0.2) > 0.1);  // pulled ~7 deg off by the minor
  const auto by_mode = est::strongest_cluster(s.view(), 1.0f, 0.9f, true);
  CHECK(by_mode.strongest.mean.theta == Approx(0.2f).margin(1e-5));
  CHECK(by_mode.strongest.particles == 70u);
  CHECK(by_mode.strongest.weight == Approx(0.7f).epsilon(1e-4));
  // Particles without modes (kUnknownMode everywhere): by mode changes nothing.
  for (std::uint32_t i = 0; i < 100; ++i) v.mode[i] = est::kUnknownMode;
  const auto none = est::strongest_cluster(s.view(), 1.0f, 0.9f, true);
  CHECK(none.strongest.mean.theta == mixed.strongest.mean.theta);
  CHECK(none.strongest.particles == 100u);
}
