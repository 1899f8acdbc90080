// The steered rangefinder's handle-position prior (est/loop/steered_scan.hpp): p(alpha_m | x) is uniform without a
// steering reading; with one it is the mass of N(s, sigma_s^2) over the angles nearest each position (the outer
// positions take everything beyond them, so the masses sum to 1 and a reading past a stop goes to the last
// position), floored so that no position is ever ruled out.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <numeric>

#include "est/loop/steered_scan.hpp"

namespace {

using Scan = est::loop::SteeredScan<64>;

double phi(double z) { return 0.5 * std::erfc(-z / std::sqrt(2.0)); }

// The Gaussian's mass over position i's angles: between the midpoints to its neighbours, unbounded at the ends.
double sector_mass(const Scan& s, std::int32_t i, double reading, double sigma) {
  const float* a = s.alphas();
  const double lo = i == 0 ? -1e300 : 0.5 * (static_cast<double>(a[i - 1]) + static_cast<double>(a[i]));
  const double hi =
      i == s.positions() - 1 ? 1e300 : 0.5 * (static_cast<double>(a[i]) + static_cast<double>(a[i + 1]));
  return phi((hi - reading) / sigma) - phi((lo - reading) / sigma);
}

est::loop::SteeredScanConfig config(std::int32_t positions, float sigma) {
  est::loop::SteeredScanConfig c;
  c.steer_max = 1.0471976f;
  c.positions = positions;
  c.reading_sigma = sigma;
  c.floor = 1.0e-3f;
  return c;
}

}  // namespace

TEST_CASE("the handle positions lie between the stops, increasing and symmetric", "[steered_scan]") {
  const est::LikelihoodField field;
  for (std::int32_t m : {2, 5, 6, 7, 16}) {
    INFO("M = " << m);
    const Scan s(field, config(m, 0.05f));
    REQUIRE(s.positions() == m);
    for (std::int32_t i = 0; i < m; ++i) {
      CHECK(s.alphas()[i] >= -1.0471976f);
      CHECK(s.alphas()[i] <= 1.0471976f);
      CHECK(s.alphas()[i] == Approx(-s.alphas()[m - 1 - i]).margin(1e-6));
      if (i > 0) CHECK(s.alphas()[i] > s.alphas()[i - 1]);
    }
  }
  const Scan many(field, config(40, 0.05f));
  CHECK(many.positions() == est::kMaxSteeringHypotheses);  // cut at the capacity
}

TEST_CASE("without a steering reading every position is equally likely", "[steered_scan]") {
  const est::LikelihoodField field;
  const Scan s(field, config(6, 0.05f));
  float probs[est::kMaxSteeringHypotheses];
  s.handle_probabilities(est::loop::ScanContext{0.0f, false}, probs);
  for (std::int32_t i = 0; i < 6; ++i) CHECK(probs[i] == Approx(1.0f / 6.0f));
  // A reading the configuration says not to use, or one without a usable spread: uniform too.
  est::loop::SteeredScanConfig ignore = config(6, 0.05f);
  ignore.use_reading = false;
  const Scan a(field, ignore);
  a.handle_probabilities(est::loop::ScanContext{0.4f, true}, probs);
  for (std::int32_t i = 0; i < 6; ++i) CHECK(probs[i] == Approx(1.0f / 6.0f));
  const Scan b(field, config(6, 0.0f));
  b.handle_probabilities(est::loop::ScanContext{0.4f, true}, probs);
  for (std::int32_t i = 0; i < 6; ++i) CHECK(probs[i] == Approx(1.0f / 6.0f));
}

TEST_CASE("with a reading each position has the Gaussian's mass over its angles, and the masses sum to 1",
          "[steered_scan]") {
  const est::LikelihoodField field;
  for (const float reading : {0.0f, 0.13f, -0.6f}) {
    INFO("reading " << reading);
    const float sigma = 0.5f;  // wide: every position's mass is above the floor, nothing is renormalized away
    const Scan s(field, config(6, sigma));
    float probs[est::kMaxSteeringHypotheses];
    s.handle_probabilities(est::loop::ScanContext{reading, true}, probs);
    double sum = 0.0, expected_sum = 0.0;
    for (std::int32_t i = 0; i < s.positions(); ++i) {
      const double want = sector_mass(s, i, static_cast<double>(reading), static_cast<double>(sigma));
      REQUIRE(want > 1e-3);
      CHECK(probs[i] == Approx(want).margin(2e-5));
      sum += static_cast<double>(probs[i]);
      expected_sum += want;
    }
    CHECK(expected_sum == Approx(1.0).margin(1e-12));  // the sectors tile the line
    CHECK(sum == Approx(1.0).margin(1e-5));
  }
  // A narrow reading concentrates on the nearest position; the sum is still 1.
  const Scan narrow(field, config(7, 0.02f));
  float probs[est::kMaxSteeringHypotheses];
  narrow.handle_probabilities(est::loop::ScanContext{narrow.alphas()[2] + 0.01f, true}, probs);
  CHECK(std::accumulate(probs, probs + 7, 0.0f) == Approx(1.0f).margin(1e-5));
  CHECK(std::max_element(probs, probs + 7) - probs == 2);
  CHECK(probs[2] > 0.99f);
}

TEST_CASE("a reading past a stop goes to the position at that stop", "[steered_scan]") {
  const est::LikelihoodField field;
  const Scan s(field, config(6, 0.05f));
  float probs[est::kMaxSteeringHypotheses];
  s.handle_probabilities(est::loop::ScanContext{1.0471976f + 0.3f, true}, probs);  // beyond the left stop
  CHECK(std::max_element(probs, probs + 6) - probs == 5);
  CHECK(probs[5] > 0.99f);
  s.handle_probabilities(est::loop::ScanContext{-2.0f, true}, probs);  // far beyond the right stop
  CHECK(std::max_element(probs, probs + 6) - probs == 0);
  CHECK(probs[0] > 0.99f);
  CHECK(std::accumulate(probs, probs + 6, 0.0f) == Approx(1.0f).margin(1e-5));
}

TEST_CASE("a reading never rules a position out: every position keeps at least the floor", "[steered_scan]") {
  const est::LikelihoodField field;
  est::loop::SteeredScanConfig c = config(6, 0.01f);
  c.floor = 2.0e-3f;
  const Scan s(field, c);
  float probs[est::kMaxSteeringHypotheses];
  s.handle_probabilities(est::loop::ScanContext{s.alphas()[0], true}, probs);  // right on the first position
  // The first has (almost) all the Gaussian's mass; the five others the floor each, then all renormalized.
  const float total = 1.0f + 5.0f * c.floor;
  for (std::int32_t i = 1; i < 6; ++i) CHECK(probs[i] == Approx(c.floor / total).epsilon(1e-3));
  CHECK(probs[0] == Approx(1.0f / total).epsilon(1e-3));
  for (std::int32_t i = 0; i < 6; ++i) CHECK(probs[i] > 0.0f);
  // A larger floor gives the far positions more, never less.
  c.floor = 1.0e-2f;
  const Scan wider(field, c);
  float more[est::kMaxSteeringHypotheses];
  wider.handle_probabilities(est::loop::ScanContext{s.alphas()[0], true}, more);
  for (std::int32_t i = 1; i < 6; ++i) CHECK(more[i] > probs[i]);
}

// Injection along the ambiguity (split): a moved particle takes another position m' with the frame turned and moved
// so that its sensor's pose is the one it had; split_share of the set moves, and a particle without a mode stays.
TEST_CASE("split moves particles to another handle position that keeps the sensor's pose", "[steered_scan]") {
  const est::LikelihoodField field;
  est::loop::SteeredScanConfig c = config(6, 0.05f);
  c.mount = {0.15f, 0.0f, {0.05f, 0.0f, 0.0f}};
  c.split_share = 0.25f;
  Scan s(field, c);
  static est::AugmentedMcl<64> mcl(est::MclConfig{}, 5u);
  mcl.initialize_gaussian({2.0f, 3.0f, 0.4f}, 0.1f, 0.1f, 64u);
  est::ParticleSetView v = mcl.particles_mutable();
  est::Pose2 before[64];
  for (std::uint32_t i = 0; i < 64; ++i) {
    v.mode[i] = i < 60 ? static_cast<std::uint8_t>(i % 6) : est::kUnknownMode;
    before[i] = v.pose(i);
  }
  std::uint8_t mode_before[64];
  std::copy(v.mode, v.mode + 64, mode_before);
  const std::uint32_t moved = s.split(mcl);
  CHECK(moved >= 8u);   // 16 draws (0.25 of 64), some the same particle or one without a mode
  CHECK(moved <= 17u);
  CHECK(s.splits() == moved);
  std::uint32_t changed = 0;
  for (std::uint32_t i = 0; i < 64; ++i) {
    INFO("particle " << i);
    if (i >= 60) {
      CHECK(v.mode[i] == est::kUnknownMode);
      CHECK(v.pose(i).x == before[i].x);
      continue;
    }
    if (v.mode[i] == mode_before[i]) {  // not drawn, or drawn twice and back: the pose it had, to rounding
      CHECK(v.pose(i).theta == Approx(before[i].theta).margin(1e-5));
      continue;
    }
    ++changed;
    const est::Pose2 was = compose(before[i], est::steered_sensor_mount(c.mount, s.alphas()[mode_before[i]]));
    const est::Pose2 now = compose(v.pose(i), est::steered_sensor_mount(c.mount, s.alphas()[v.mode[i]]));
    CHECK(now.x == Approx(was.x).margin(1e-5));
    CHECK(now.y == Approx(was.y).margin(1e-5));
    CHECK(std::abs(est::fmath::normalize_angle(now.theta - was.theta)) < 1e-5f);
    // The frame turned by the handle's difference.
    CHECK(std::abs(est::fmath::normalize_angle(v.pose(i).theta - before[i].theta -
                                        (s.alphas()[mode_before[i]] - s.alphas()[v.mode[i]]))) < 1e-5f);
  }
  CHECK(changed >= 1u);
  CHECK(changed <= moved);
  // The baseline (positions = 0) carries no modes and splits nothing.
  Scan exact(field, config(0, 0.05f));
  CHECK(exact.modes() == 0);
  CHECK(exact.split(mcl) == 0u);
}
