#include <catch2/catch.hpp>

#include <cmath>
#include <vector>

#include "est/random/samplers.hpp"
#include "maps/learn_intrinsic_parameters.hpp"

namespace {

// Readings drawn from the beam model with known parameters (z* uniform in [1, 8] m, range_max 10 m).
std::vector<est::sim::RangeSample> synthetic(const est::BeamModelParams& p, std::size_t n, std::uint64_t seed) {
  est::Rng rng(seed);
  std::vector<est::sim::RangeSample> out;
  const double zm = p.range_max, lambda = p.lambda_short;
  const double c_hit = p.z_hit, c_short = c_hit + double(p.z_short), c_max = c_short + double(p.z_max);
  while (out.size() < n) {
    const double zs = double(rng.uniform(1.0f, 8.0f));
    const double u = double(rng.uniform());
    double z = 0.0;
    if (u < c_hit) {
      do z = zs + double(est::sample_normal(rng, p.sigma_hit));
      while (z < 0.0 || z >= zm);
    } else if (u < c_short) {
      z = -std::log1p(-double(rng.uniform()) * -std::expm1(-lambda * zs)) / lambda;
    } else if (u < c_max) {
      z = zm;
    } else {
      z = double(rng.uniform()) * zm;
    }
    out.push_back({z, zs});
  }
  return out;
}

}  // namespace

TEST_CASE("EM recovers the beam model's intrinsic parameters from synthetic readings", "[learn_intrinsic_parameters]") {
  est::BeamModelParams truth;
  truth.z_hit = 0.7f;
  truth.z_short = 0.15f;
  truth.z_max = 0.05f;
  truth.z_rand = 0.1f;
  truth.sigma_hit = 0.15f;
  truth.lambda_short = 0.6f;
  truth.range_max = 10.0f;
  const auto data = synthetic(truth, 20000, 17u);

  est::BeamModelParams init = truth;
  init.z_hit = init.z_short = init.z_max = init.z_rand = 0.25f;
  init.sigma_hit = 0.5f;
  init.lambda_short = 1.5f;
  const est::sim::LearnResult r = est::sim::learn_intrinsic_parameters(data, init);
  INFO("z_hit " << r.params.z_hit << " z_short " << r.params.z_short << " z_max " << r.params.z_max << " z_rand "
                << r.params.z_rand << " sigma " << r.params.sigma_hit << " lambda " << r.params.lambda_short
                << " after " << r.iterations << " iterations");
  CHECK(r.converged);
  // Weights within 0.015 (4 standard errors of a proportion at n = 20 000 is 0.013), sigma within 3 %,
  // lambda within 10 % (about 3 000 short readings, partly confused with the uniform part).
  CHECK(r.params.z_hit == Approx(0.7f).margin(0.015));
  CHECK(r.params.z_short == Approx(0.15f).margin(0.015));
  CHECK(r.params.z_max == Approx(0.05f).margin(0.015));
  CHECK(r.params.z_rand == Approx(0.1f).margin(0.015));
  CHECK(r.params.sigma_hit == Approx(0.15f).epsilon(0.03));
  CHECK(r.params.lambda_short == Approx(0.6f).epsilon(0.10));
  // The learned parameters are accepted by the firmware model.
  est::BeamRangeFinderModel m;
  CHECK(m.configure(r.params) == est::SensorModelStatus::ok);
}

TEST_CASE("EM refuses empty and non-finite data", "[learn_intrinsic_parameters]") {
  const est::BeamModelParams p;
  CHECK_THROWS_AS(est::sim::learn_intrinsic_parameters({}, p), std::invalid_argument);
  CHECK_THROWS_AS(est::sim::learn_intrinsic_parameters({{std::nan(""), 1.0}}, p), std::invalid_argument);
  CHECK_THROWS_AS(est::sim::learn_intrinsic_parameters({{-1.0, 1.0}}, p), std::invalid_argument);
}
