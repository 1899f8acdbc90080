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

namespace {

// The beacon ranges measured `copies` times over: a measurement of 3 * copies factors, each at most e^0.
auto repeated_beacons(const Ranges& z, int copies) {
  return [z, copies](const est::Pose2& p) { return static_cast<float>(copies) * beacon_model(z)(p); };
}
est::MeasurementScale beacon_scale(int copies) { return {3 * copies, 0.0f}; }

// Every particle gets the same log-likelihood: the per-factor fit is exactly `fit`.
auto uniform_fit(float fit, int factors) {
  return [fit, factors](const est::Pose2&) { return fit * static_cast<float>(factors); };
}

}  // namespace

TEST_CASE("with a measurement scale the recovery statistic is the per-beam fit and starts from a perfect fit",
          "[mcl]") {
  est::MclConfig cfg;
  static est::AugmentedMcl<500> mcl(cfg, 31u);
  mcl.initialize_gaussian({4.0f, 4.0f, 0.0f}, 0.2f, 0.05f, 500);
  est::Rng world(3u);
  const auto r = mcl.correct(repeated_beacons(measure({4.0f, 4.0f, 0.0f}, &world), 20), beacon_scale(20));
  CHECK(r.fit == Approx(r.log_mean_likelihood / 60.0f).epsilon(1e-5));
  CHECK(r.fit <= 0.0f);
  // Lines 10-11 from w_slow = w_fast = 1 (a perfect fit), not from the first value.
  const double w = std::exp(static_cast<double>(r.fit));
  const double as = static_cast<double>(cfg.alpha_slow), af = static_cast<double>(cfg.alpha_fast);
  CHECK(mcl.log_w_slow() == Approx(std::log(1.0 - as + as * w)).margin(1e-5));
  CHECK(mcl.log_w_fast() == Approx(std::log(1.0 - af + af * w)).margin(1e-5));
  // Without a scale: the book's log w_avg, and the averages start there.
  static est::AugmentedMcl<500> book(cfg, 31u);
  book.initialize_gaussian({4.0f, 4.0f, 0.0f}, 0.2f, 0.05f, 500);
  const auto rb = book.correct(repeated_beacons(measure({4.0f, 4.0f, 0.0f}, nullptr), 20));
  CHECK(rb.fit == rb.log_mean_likelihood);
  CHECK(book.log_w_slow() == rb.log_mean_likelihood);
}

TEST_CASE("a scan that changes size changes w_avg by many nats but injects nothing with the per-beam fit",
          "[mcl]") {
  // Tracking a robot standing still while the number of readings alternates between 30 and 60 (max readings
  // skipped, beams on clutter...): the scan's log-likelihood halves and doubles, its per-beam fit does not move.
  const auto run = [](bool per_beam) {
    est::MclConfig cfg;
    cfg.alpha_slow = 0.02f;
    cfg.alpha_fast = 0.3f;
    static est::AugmentedMcl<1000> mcl(cfg, 1u);
    mcl = est::AugmentedMcl<1000>(cfg, 41u);
    mcl.initialize_gaussian({3.0f, 5.0f, 0.0f}, 0.05f, 0.02f, 1000);
    est::Rng world(8u);
    const est::Pose2 truth{3.0f, 5.0f, 0.0f};
    for (int t = 0; t < 60; ++t) {
      mcl.predict<Walk>({0.0f, 0.0f, 0.0f}, {0.02f, 0.01f});
      const int copies = t % 2 == 0 ? 10 : 20;
      const Ranges z = measure(truth, &world);
      if (per_beam)
        mcl.correct(repeated_beacons(z, copies), beacon_scale(copies));
      else
        mcl.correct(repeated_beacons(z, copies));
      mcl.resample(uniform_box);
    }
    return mcl.counters().injected_particles;
  };
  const std::uint32_t per_beam = run(true), book = run(false);
  INFO("injected: per-beam fit " << per_beam << ", the book's w_avg " << book);
  CHECK(per_beam == 0u);
  CHECK(book > 1000u);  // the book's statistic injects on most resamplings
}

TEST_CASE("a lost scan injects at once, a mild deficit only after the patience, a fine fit never", "[mcl]") {
  est::MclConfig cfg;
  cfg.alpha_slow = 0.02f;
  cfg.alpha_fast = 0.3f;
  constexpr int kFactors = 60;
  const auto settle = [&](est::AugmentedMcl<200>& mcl) {
    mcl.initialize_gaussian({5.0f, 5.0f, 0.0f}, 0.1f, 0.05f, 200);
    for (int t = 0; t < 30; ++t) {  // tracking at a fit of -0.05 nats per beam
      mcl.correct(uniform_fit(-0.05f, kFactors), {kFactors, 0.0f});
      CHECK(mcl.injection_probability() == 0.0f);
      mcl.resample(uniform_box);
    }
  };
  static est::AugmentedMcl<200> mcl(cfg, 5u);
  mcl = est::AugmentedMcl<200>(cfg, 5u);
  settle(mcl);
  CHECK(mcl.counters().injected_particles == 0u);

  // Lost: every beam ~2 nats below the peak.
  mcl.correct(uniform_fit(-2.0f, kFactors), {kFactors, 0.0f});
  CHECK(mcl.last_deficit() >= cfg.recovery_lost_deficit);
  CHECK(mcl.injection_probability() > 0.0f);

  // Mild: 0.6 nats per beam below, for longer than the patience.
  mcl = est::AugmentedMcl<200>(cfg, 6u);
  settle(mcl);
  int first_injection = -1;
  for (int t = 0; t < 3 * static_cast<int>(cfg.recovery_patience) && first_injection < 0; ++t) {
    mcl.correct(uniform_fit(-0.6f, kFactors), {kFactors, 0.0f});
    CHECK(mcl.last_deficit() < cfg.recovery_lost_deficit);
    if (mcl.injection_probability() > 0.0f) first_injection = t;
    mcl.resample(uniform_box);
  }
  INFO("first injection after " << first_injection << " mild corrections");
  CHECK(first_injection >= static_cast<int>(cfg.recovery_patience) - 1);
  CHECK(first_injection < 2 * static_cast<int>(cfg.recovery_patience));
}

TEST_CASE("when the injected particles take the weight the filter holds the injection while the fit improves",
          "[mcl]") {
  est::MclConfig cfg;
  cfg.alpha_slow = 0.02f;
  cfg.alpha_fast = 0.3f;
  constexpr int kFactors = 60;
  static est::AugmentedMcl<1000> mcl(cfg, 9u);
  mcl = est::AugmentedMcl<1000>(cfg, 9u);
  mcl.initialize_gaussian({2.0f, 2.0f, 0.0f}, 0.1f, 0.05f, 1000);
  for (int t = 0; t < 20; ++t) {
    mcl.correct(uniform_fit(-0.05f, kFactors), {kFactors, 0.0f});
    mcl.resample(uniform_box);
  }
  // Kidnapped into the half x > 5: the old cloud (x ~ 2) misses every beam by 3 nats, x > 5 fits, better the
  // closer to (7.5, 6).
  const auto kidnapped = [](const est::Pose2& p) {
    const float d2 = (p.x - 7.5f) * (p.x - 7.5f) + (p.y - 6.0f) * (p.y - 6.0f);
    return static_cast<float>(kFactors) * (p.x > 5.0f ? -0.1f - 0.1f * d2 : -3.0f);
  };
  mcl.correct(kidnapped, {kFactors, 0.0f});
  REQUIRE(mcl.injection_probability() > 0.0f);  // lost: inject at once
  mcl.resample(uniform_box);
  REQUIRE(mcl.counters().injected_particles > 0u);
  const std::uint32_t injected = mcl.counters().injected_particles;
  mcl.correct(kidnapped, {kFactors, 0.0f});
  CHECK(mcl.last_found());                        // the random particles in x > 5 took the weight
  CHECK(mcl.injection_probability() == 0.0f);     // held: the found cloud converges without random particles
  mcl.resample(uniform_box);
  CHECK(mcl.counters().injected_particles == injected);
  CHECK(mcl.cluster_estimate().strongest.mean.x > 5.0f);
}

TEST_CASE("KLD resampling counts the bins of the samples drawn, not of the weighted set", "[mcl][kld]") {
  // 5000 particles over the whole box, nearly all the weight within 5 cm of (5, 5): the draws fall in one or two
  // bins, so table 8.4 asks for n_min. (Counting the bins of the weighted set, as before, asked for all 5000.)
  est::MclConfig cfg;
  cfg.kld = true;
  cfg.recovery = false;
  cfg.kld_config.n_min = 150;
  static est::AugmentedMcl<5000> mcl(cfg, 12u);
  mcl = est::AugmentedMcl<5000>(cfg, 12u);
  mcl.initialize_global(uniform_box, 5000);
  auto v = mcl.particles_mutable();
  v.x[0] = 5.0f;
  v.y[0] = 5.0f;
  v.theta[0] = 0.01f;
  mcl.correct([](const est::Pose2& p) {
    const float d2 = (p.x - 5.0f) * (p.x - 5.0f) + (p.y - 5.0f) * (p.y - 5.0f);
    return -2000.0f * d2;
  });
  REQUIRE(mcl.resample(uniform_box, true));
  CHECK(mcl.particles().count == cfg.kld_config.n_min);
  CHECK(mcl.counters().drawn_particles == cfg.kld_config.n_min);
}

TEST_CASE("random draws open new bins and take KLD's count to the capacity", "[mcl][kld]") {
  est::MclConfig cfg;
  cfg.kld = true;
  static est::AugmentedMcl<3000> mcl(cfg, 13u);
  mcl = est::AugmentedMcl<3000>(cfg, 13u);
  mcl.initialize_gaussian({5.0f, 5.0f, 0.0f}, 0.05f, 0.02f, 500);
  mcl.correct([](const est::Pose2&) { return std::numeric_limits<float>::quiet_NaN(); });  // forces recovery
  REQUIRE(mcl.injection_probability() == Approx(cfg.max_injection_fraction));
  REQUIRE(mcl.resample(uniform_box));
  CHECK(mcl.particles().count == 3000u);
  const double share = static_cast<double>(mcl.counters().injected_particles) / 3000.0;
  CHECK(share == Approx(cfg.max_injection_fraction).margin(0.05));
}

TEST_CASE("KLD resampling keeps the low-variance sampler's copy counts", "[mcl][kld]") {
  // Three particles in three bins with weights 0.5, 0.3, 0.2: table 8.4 asks for n_min = 100 and the comb draws
  // each floor or ceil of 100 w_i times.
  est::MclConfig cfg;
  cfg.kld = true;
  cfg.recovery = false;
  cfg.kld_config.n_min = 100;
  static est::AugmentedMcl<200> mcl(cfg, 14u);
  mcl = est::AugmentedMcl<200>(cfg, 14u);
  mcl.initialize_gaussian({0.0f, 0.0f, 0.0f}, 0.0f, 0.0f, 3);
  auto v = mcl.particles_mutable();
  const float xs[3] = {1.0f, 4.0f, 7.0f}, ws[3] = {0.5f, 0.3f, 0.2f};
  for (int i = 0; i < 3; ++i) {
    v.x[i] = xs[i];
    v.y[i] = 1.0f;
    v.theta[i] = 0.0f;
    v.log_w[i] = std::log(ws[i]);
  }
  REQUIRE(mcl.resample(uniform_box, true));
  const auto p = mcl.particles();
  REQUIRE(p.count == 100u);
  int copies[3] = {0, 0, 0};
  for (std::uint32_t i = 0; i < p.count; ++i)
    for (int k = 0; k < 3; ++k) copies[k] += p.x[i] == xs[k] ? 1 : 0;
  for (int k = 0; k < 3; ++k) CHECK(std::abs(copies[k] - static_cast<int>(100.0f * ws[k])) <= 1);
}
