#include <catch2/catch.hpp>
#include <cmath>
#include <limits>

#include "est/filter/augmented_mcl.hpp"
#include "est/motion/motion_batch.hpp"
#include "est/util/digest.hpp"

// Filter-logic tests with a minimal motion model and range beacons, so they do not depend on the full sensor
// models; tracking and global localization with the real models and maps are in test_mcl_scenarios.cpp.
namespace {

struct Walk {  // x_t = x_t-1 + u + N(0, sigma^2) per axis, in the world frame
  using State = est::Pose2;
  struct Control {
    float dx, dy, dtheta;
  };
  struct Params {
    float sigma_xy, sigma_theta;
  };
  static est::MotionStatus check(const Control& u, const Params&) {
    return std::isfinite(u.dx) && std::isfinite(u.dy) && std::isfinite(u.dtheta) ? est::MotionStatus::ok
                                                                                   : est::MotionStatus::rejected_nonfinite;
  }
  static State sample(const State& x, const Control& u, const Params& p, est::Rng& rng) {
    return {x.x + u.dx + est::sample_normal(rng, p.sigma_xy), x.y + u.dy + est::sample_normal(rng, p.sigma_xy),
            est::fmath::normalize_angle(x.theta + u.dtheta + est::sample_normal(rng, p.sigma_theta))};
  }
};

// Three beacons placed without symmetry in a 10 x 10 m box; each measures its Euclidean range with sigma 0.2 m.
constexpr float kBeacons[3][2] = {{1.0f, 1.0f}, {9.0f, 2.5f}, {3.0f, 8.5f}};
constexpr float kSigmaRange = 0.2f;

struct Ranges {
  float r[3];
};
Ranges measure(const est::Pose2& p, est::Rng* noise) {
  Ranges z{};
  for (int b = 0; b < 3; ++b) {
    const float dx = p.x - kBeacons[b][0], dy = p.y - kBeacons[b][1];
    z.r[b] = std::sqrt(dx * dx + dy * dy) + (noise ? est::sample_normal(*noise, kSigmaRange) : 0.0f);
  }
  return z;
}
auto beacon_model(const Ranges& z) {
  return [z](const est::Pose2& p) {
    const Ranges h = measure(p, nullptr);
    float ll = 0.0f;
    for (int b = 0; b < 3; ++b) {
      const float e = (z.r[b] - h.r[b]) / kSigmaRange;
      ll += -0.5f * e * e;
    }
    return ll;
  };
}
// Uniform over the box: the recovery source for these tests.
const auto uniform_box = [](est::Rng& rng, est::Pose2& p) {
  p = {rng.uniform(0.0f, 10.0f), rng.uniform(0.0f, 10.0f), rng.uniform(-3.14159f, 3.14159f)};
  return true;
};

float position_error(const est::Pose2& a, const est::Pose2& b) { return std::hypot(a.x - b.x, a.y - b.y); }

}  // namespace

TEST_CASE("global localization from a uniform start converges to the true pose", "[mcl]") {
  est::MclConfig cfg;
  static est::AugmentedMcl<2000> mcl(cfg, 17u);
  mcl.initialize_global(uniform_box, 2000);
  est::Rng world(5u);
  est::Pose2 truth{6.0f, 4.0f, 0.5f};
  const Walk::Params params{0.05f, 0.02f};
  for (int t = 0; t < 30; ++t) {
    const Walk::Control u{0.05f, 0.02f, 0.0f};
    truth = {truth.x + u.dx, truth.y + u.dy, truth.theta};
    mcl.predict<Walk>(u, params);
    mcl.correct(beacon_model(measure(truth, &world)));
    mcl.resample(uniform_box);
  }
  const auto e = mcl.cluster_estimate().strongest;
  INFO("estimate " << e.mean.x << ", " << e.mean.y << " truth " << truth.x << ", " << truth.y);
  CHECK(position_error(e.mean, truth) < 0.3f);  // ~ 1.5 sigma of one range measurement
  CHECK(mcl.counters().resamplings > 0u);
}

TEST_CASE("a kidnapped robot is recovered by augmented MCL and not without recovery", "[mcl]") {
  auto run = [](bool recovery) {
    est::MclConfig cfg;
    cfg.recovery = recovery;
    static est::AugmentedMcl<1000> mcl(cfg, 1u);
    mcl = est::AugmentedMcl<1000>(cfg, 23u);
    mcl.initialize_gaussian({2.0f, 2.0f, 0.0f}, 0.1f, 0.05f, 1000);
    est::Rng world(6u);
    est::Pose2 truth{2.0f, 2.0f, 0.0f};
    const Walk::Params params{0.03f, 0.01f};
    for (int t = 0; t < 20; ++t) {  // track first
      mcl.predict<Walk>({0.0f, 0.0f, 0.0f}, params);
      mcl.correct(beacon_model(measure(truth, &world)));
      mcl.resample(uniform_box);
    }
    truth = {7.5f, 6.0f, 0.0f};  // kidnapped: moved without telling the filter
    int recovered_at = -1;
    // Without injection the cloud can still crawl towards the new pose, a few motion sigmas per step (it gets there
    // after ~80 steps here); recovery must beat that by far, so the window is 40 steps.
    for (int t = 0; t < 40 && recovered_at < 0; ++t) {
      mcl.predict<Walk>({0.0f, 0.0f, 0.0f}, params);
      mcl.correct(beacon_model(measure(truth, &world)));
      mcl.resample(uniform_box);
      if (position_error(mcl.cluster_estimate().strongest.mean, truth) < 0.5f) recovered_at = t;
    }
    return std::make_pair(recovered_at, mcl.counters().injected_particles);
  };
  const auto with = run(true);
  const auto without = run(false);
  INFO("recovered after " << with.first << " steps, " << with.second << " particles injected");
  CHECK(with.first >= 0);
  CHECK(with.first < 25);
  CHECK(with.second > 0u);
  CHECK(without.first == -1);
  CHECK(without.second == 0u);
}

TEST_CASE("NaN likelihoods never produce a NaN estimate and force recovery", "[mcl]") {
  est::MclConfig cfg;
  static est::AugmentedMcl<500> mcl(cfg, 2u);
  mcl.initialize_gaussian({5.0f, 5.0f, 0.0f}, 0.2f, 0.1f, 500);
  const auto report =
      mcl.correct([](const est::Pose2&) { return std::numeric_limits<float>::quiet_NaN(); });
  CHECK(report.degenerate);
  CHECK(mcl.counters().degenerate_corrections == 1u);
  CHECK(mcl.counters().nonfinite_weights == 500u);
  const auto e = mcl.estimate();
  CHECK(e.mean.is_finite());
  CHECK(e.covariance.allFinite());
  CHECK(mcl.injection_probability() == Approx(cfg.max_injection_fraction));
  CHECK(mcl.resample(uniform_box));
  CHECK(mcl.counters().injected_particles > 150u);  // ~ half of 500
}

TEST_CASE("a refused control leaves the particles untouched and is counted", "[mcl]") {
  est::MclConfig cfg;
  static est::AugmentedMcl<100> mcl(cfg, 3u);
  mcl.initialize_gaussian({1.0f, 1.0f, 0.0f}, 0.1f, 0.1f, 100);
  const float x0 = mcl.particles().x[0];
  const auto s = mcl.predict<Walk>({std::numeric_limits<float>::quiet_NaN(), 0.0f, 0.0f}, {0.1f, 0.1f});
  CHECK(s == est::MotionStatus::rejected_nonfinite);
  CHECK(mcl.counters().rejected_controls == 1u);
  CHECK(mcl.particles().x[0] == x0);
}

TEST_CASE("map-conditioned prediction down-weights particles that land in occupied space", "[mcl]") {
  est::MclConfig cfg;
  static est::AugmentedMcl<1000> mcl(cfg, 4u);
  mcl.initialize_gaussian({0.0f, 0.0f, 0.0f}, 0.5f, 0.1f, 1000);
  const auto free_left = [](float x, float) { return x < 0.0f; };  // a wall fills x >= 0
  mcl.predict_in_map<Walk>({0.0f, 0.0f, 0.0f}, {0.01f, 0.01f}, free_left);
  const auto p = mcl.particles();
  double w_occupied = 0.0;
  for (std::uint32_t i = 0; i < p.count; ++i)
    if (p.x[i] >= 0.0f) w_occupied += std::exp(static_cast<double>(p.log_w[i]));
  // Half the particles sit in the wall with likelihood ratio 0.01: their share is 0.01 / 1.01 (+- sampling).
  CHECK(w_occupied == Approx(0.01 / 1.01).margin(0.003));
  CHECK(mcl.counters().map_penalized > 400u);
  CHECK(mcl.estimate().mean.x < -0.3f);
}

TEST_CASE("KLD-adaptive MCL shrinks the particle count once localized", "[mcl]") {
  est::MclConfig cfg;
  cfg.kld = true;
  static est::AugmentedMcl<5000> mcl(cfg, 5u);
  mcl.initialize_global(uniform_box, 5000);
  est::Rng world(7u);
  const est::Pose2 truth{4.0f, 6.0f, 0.0f};
  for (int t = 0; t < 25; ++t) {
    mcl.predict<Walk>({0.0f, 0.0f, 0.0f}, {0.03f, 0.01f});
    mcl.correct(beacon_model(measure(truth, &world)));
    mcl.resample(uniform_box, true);
  }
  INFO("particles after convergence: " << mcl.particles().count);
  CHECK(mcl.particles().count < 1500u);
  CHECK(mcl.particles().count >= cfg.kld_config.n_min);
  CHECK(position_error(mcl.estimate().mean, truth) < 0.3f);
}

TEST_CASE("same seed and inputs give bit-identical particle sets", "[mcl]") {
  auto run = [] {
    est::MclConfig cfg;
    static est::AugmentedMcl<800> mcl(cfg, 0u);
    mcl = est::AugmentedMcl<800>(cfg, 99u);
    mcl.initialize_global(uniform_box, 800);
    est::Rng world(1u);
    for (int t = 0; t < 10; ++t) {
      mcl.predict<Walk>({0.1f, 0.0f, 0.01f}, {0.05f, 0.02f});
      mcl.correct(beacon_model(measure({5.0f, 5.0f, 0.0f}, &world)));
      mcl.resample(uniform_box);
    }
    est::Digest d;
    const auto p = mcl.particles();
    for (std::uint32_t i = 0; i < p.count; ++i) {
      d.add(p.x[i]);
      d.add(p.y[i]);
      d.add(p.theta[i]);
      d.add(p.log_w[i]);
    }
    return d.value();
  };
  CHECK(run() == run());
}

TEST_CASE("correct_batch gives the bits of correct; predict_batch refuses and counts like predict", "[mcl]") {
  est::MclConfig cfg;
  static est::AugmentedMcl<300> a(cfg, 0u), b(cfg, 0u);
  a = est::AugmentedMcl<300>(cfg, 8u);
  b = est::AugmentedMcl<300>(cfg, 8u);
  a.initialize_global(uniform_box, 300);
  b.initialize_global(uniform_box, 300);
  const auto model = beacon_model(measure({4.0f, 4.0f, 0.0f}, nullptr));
  const auto ra = a.correct(model);
  const auto rb = b.correct_batch([&](est::ConstParticleSetView p, float* out) {
    for (std::uint32_t i = 0; i < p.count; ++i) out[i] = model(p.pose(i));
  });
  CHECK(ra.log_mean_likelihood == rb.log_mean_likelihood);
  for (std::uint32_t i = 0; i < 300; ++i) CHECK(a.particles().log_w[i] == b.particles().log_w[i]);
  // Walk has no batched form: predict_batch falls back to its sampler, so the sets stay equal.
  a.predict<Walk>({0.1f, 0.0f, 0.0f}, {0.05f, 0.01f});
  b.predict_batch<Walk>({0.1f, 0.0f, 0.0f}, {0.05f, 0.01f});
  CHECK(a.particles().x[17] == b.particles().x[17]);
  CHECK(b.predict_batch<Walk>({std::numeric_limits<float>::quiet_NaN(), 0.0f, 0.0f}, {0.05f, 0.01f}) ==
        est::MotionStatus::rejected_nonfinite);
  CHECK(b.counters().rejected_controls == 1u);
  CHECK(b.counters().predictions == 1u);
}
