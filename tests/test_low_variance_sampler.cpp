#include <catch2/catch.hpp>
#include <cmath>
#include <vector>

#include "est/filter/log_weights.hpp"
#include "est/filter/low_variance_sampler.hpp"
#include "est/filter/particle_set.hpp"

namespace {
// A set whose particle i has x = i and weight proportional to w[i].
template <std::uint32_t N>
void fill(est::ParticleSet<N>& s, const std::vector<double>& w) {
  s.set_count(static_cast<std::uint32_t>(w.size()));
  auto v = s.view();
  for (std::uint32_t i = 0; i < v.count; ++i) {
    v.x[i] = static_cast<float>(i);
    v.y[i] = 0.0f;
    v.theta[i] = 0.0f;
    v.log_w[i] = w[i] > 0.0 ? static_cast<float>(std::log(w[i])) : -1e30f;
  }
  est::normalize_log_weights(v.log_w, v.count);
}
}  // namespace

TEST_CASE("low-variance sampler draws each particle floor(M w) or ceil(M w) times", "[resampling]") {
  // The defining property of systematic resampling (Thrun table 4.4): the count of particle i differs from M w_i
  // by less than one, for every random offset.
  static est::ParticleSet<1024> in, out;
  est::Rng rng(3u);
  std::vector<double> w(97);
  double total = 0.0;
  for (std::size_t i = 0; i < w.size(); ++i) total += (w[i] = 0.1 + static_cast<double>((i * 37) % 11));
  fill(in, w);
  for (int trial = 0; trial < 50; ++trial) {
    const std::uint32_t m = 1000;
    auto o = out.view();
    REQUIRE(est::low_variance_sampler(in.view(), o, m, rng) == m);
    std::vector<int> count(w.size(), 0);
    for (std::uint32_t k = 0; k < m; ++k) ++count[static_cast<std::size_t>(o.x[k])];
    for (std::size_t i = 0; i < w.size(); ++i) {
      const double expected = m * w[i] / total;
      INFO("particle " << i << " expected " << expected << " drawn " << count[i]);
      // float cumulative sums over 97 weights: allow 1e-3 of slack past the exact floor/ceil bound.
      CHECK(std::abs(count[i] - expected) < 1.0 + 1e-3 * m);
    }
    for (std::uint32_t k = 0; k < m; ++k) CHECK(o.log_w[k] == Approx(-std::log(1000.0)));
  }
}

TEST_CASE("low-variance sampler never draws a zero-weight particle and keeps the output ordered", "[resampling]") {
  static est::ParticleSet<64> in, out;
  est::Rng rng(11u);
  fill(in, {0.0, 1.0, 0.0, 0.0, 3.0, 0.0});
  auto o = out.view();
  est::low_variance_sampler(in.view(), o, 64u, rng);
  int ones = 0;
  for (std::uint32_t k = 0; k < 64; ++k) {
    CHECK((o.x[k] == 1.0f || o.x[k] == 4.0f));
    if (o.x[k] == 1.0f) ++ones;
    if (k > 0) CHECK(o.x[k] >= o.x[k - 1]);
  }
  CHECK(ones == 16);  // exactly 64 * 1/4
}

TEST_CASE("low-variance sampler clamps to the output capacity and handles empty input", "[resampling]") {
  static est::ParticleSet<8> in, out;
  est::Rng rng(1u);
  fill(in, {1.0, 1.0});
  auto o = out.view();
  CHECK(est::low_variance_sampler(in.view(), o, 100u, rng) == 8u);
  in.set_count(0);
  CHECK(est::low_variance_sampler(in.view(), o, 5u, rng) == 0u);
}
