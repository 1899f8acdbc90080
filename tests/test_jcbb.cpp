#include "est/assoc/jcbb.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <vector>

#include <Eigen/Dense>

#include "est/filter/ekf_localization.hpp"
#include "est/motion/velocity_model.hpp"
#include "est/random/xoshiro128.hpp"

namespace {

using Jcbb = est::JointCompatibility<4, 6>;

// What a robot at `truth` sees of landmark l: range and bearing, noiseless.
est::JcbbSighting sight(const Eigen::Vector3f& truth, const est::Landmark& l, float sr = 0.05f, float sb = 0.01f) {
  const float dx = l.x - truth(0), dy = l.y - truth(1);
  return {std::sqrt(dx * dx + dy * dy), est::fmath::normalize_angle(std::atan2(dy, dx) - truth(2)), sr, sb};
}

// The joint Mahalanobis distance of an assignment computed directly, nu^T (H P H^T + R)^-1 nu, in double; -1 if a
// pair is not formed.
double direct_joint_nis(const Eigen::Vector3f& mu, const Eigen::Matrix3f& P, const std::vector<est::JcbbSighting>& z,
                        const est::LandmarkMap& map, const std::vector<int>& a) {
  std::vector<int> rows;
  for (std::size_t i = 0; i < a.size(); ++i)
    if (a[i] >= 0) rows.push_back(static_cast<int>(i));
  const int k = static_cast<int>(rows.size());
  if (k == 0) return 0.0;
  // Dynamic sizes of at most 8 rows: no heap (est/eigen.hpp forbids it).
  using Mat = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, 8, 8>;
  using Vec = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, 8, 1>;
  Eigen::Matrix<double, Eigen::Dynamic, 3, 0, 8, 3> H(2 * k, 3);
  Mat R = Mat::Zero(2 * k, 2 * k);
  Vec nu(2 * k);
  for (int r = 0; r < k; ++r) {
    const auto& s = z[static_cast<std::size_t>(rows[static_cast<std::size_t>(r)])];
    const est::Landmark& l = map[a[static_cast<std::size_t>(rows[static_cast<std::size_t>(r)])]];
    const auto h = est::range_bearing_measurement<3>(mu, Eigen::Vector2f(l.x, l.y));
    H.block(2 * r, 0, 2, 3) = h.H_robot.cast<double>();
    nu(2 * r) = s.range - h.z(0);
    nu(2 * r + 1) = est::fmath::normalize_angle(s.bearing - h.z(1));
    R(2 * r, 2 * r) = s.sigma_range * s.sigma_range;
    R(2 * r + 1, 2 * r + 1) = s.sigma_bearing * s.sigma_bearing;
  }
  const Mat S = H * P.cast<double>() * H.transpose() + R;
  const Vec x = S.ldlt().solve(nu);
  return nu.dot(x);
}

}  // namespace

TEST_CASE("jcbb pairs a frame right where individual nearest neighbour picks the wrong landmark", "[jcbb]") {
  // Three posts ahead 1 m apart and one to the left. The robot is 0.6 m to the right of its belief: alone, the
  // sighting of post 0 is nearer post 1's prediction (and post 1's nearer post 2's), a shift the other way; only
  // the left post's range tells the true shift, and with it the first two cannot pair with posts 1 and 2.
  const est::Landmark lm[] = {{5.0f, 0.0f, 0.0f}, {5.0f, 1.0f, 0.0f}, {5.0f, 2.0f, 0.0f}, {0.0f, 5.0f, 0.0f}};
  const est::LandmarkMap map(lm, 4);
  const Eigen::Vector3f mu(0.0f, 0.0f, 0.0f), truth(0.0f, -0.6f, 0.0f);
  Eigen::Matrix3f P = Eigen::Matrix3f::Zero();
  P(0, 0) = P(1, 1) = 0.16f;
  P(2, 2) = 0.02f * 0.02f;
  const est::JcbbSighting z[] = {sight(truth, lm[0]), sight(truth, lm[1]), sight(truth, lm[3])};

  // Table 7.3 with gating, one sighting at a time from the same belief: the wrong posts.
  est::EkfLocalization<est::VelocityMotionModel> ekf;
  REQUIRE(ekf.init(est::Pose2{mu(0), mu(1), mu(2)}, P));
  const est::LandmarkNoise noise{0.05f, 0.01f, 0.0f};
  auto copy = ekf;
  CHECK(copy.correct_range_bearing_unknown({z[0].range, z[0].bearing, 0.0f}, map, noise).landmark == 1);
  copy = ekf;
  CHECK(copy.correct_range_bearing_unknown({z[1].range, z[1].bearing, 0.0f}, map, noise).landmark == 2);

  Jcbb jcbb;
  const est::JcbbParams params;
  const auto r = jcbb.associate(mu, P, z, 3, map, params);
  REQUIRE(r.ok);
  CHECK(r.paired == 3);
  CHECK(r.landmark_of[0] == 0);
  CHECK(r.landmark_of[1] == 1);
  CHECK(r.landmark_of[2] == 3);
  CHECK_FALSE(r.node_cap_hit);
  // The nearest neighbours' choice with the left post is not jointly compatible.
  const std::vector<est::JcbbSighting> zv(z, z + 3);
  CHECK(direct_joint_nis(mu, P, zv, map, {1, 2, 3}) > static_cast<double>(params.joint_gate(3)));
  CHECK(static_cast<double>(r.joint_nis) == Approx(direct_joint_nis(mu, P, zv, map, {0, 1, 3})).epsilon(1e-3).margin(1e-3));
}

TEST_CASE("jcbb equals an exhaustive search over every assignment on random frames", "[jcbb]") {
  est::Rng rng(7u);
  std::vector<est::Landmark> lm;
  for (int j = 0; j < 9; ++j) lm.push_back({rng.uniform(-4.0f, 4.0f), rng.uniform(-4.0f, 4.0f), 0.0f});
  const est::LandmarkMap map(lm.data(), static_cast<std::int32_t>(lm.size()));
  est::JointCompatibility<4, 9> jcbb;
  const est::JcbbParams params;
  int nontrivial = 0;
  for (int t = 0; t < 200; ++t) {
    const Eigen::Vector3f truth(rng.uniform(-1.0f, 1.0f), rng.uniform(-1.0f, 1.0f), rng.uniform(-3.0f, 3.0f));
    const float s_xy = rng.uniform(0.05f, 0.6f), s_th = rng.uniform(0.01f, 0.2f);
    const Eigen::Vector3f mu = truth + Eigen::Vector3f(rng.uniform(-s_xy, s_xy), rng.uniform(-s_xy, s_xy),
                                                       rng.uniform(-s_th, s_th));
    Eigen::Matrix3f P = Eigen::Matrix3f::Zero();
    P(0, 0) = P(1, 1) = s_xy * s_xy;
    P(2, 2) = s_th * s_th;
    const int n = 1 + static_cast<int>(rng.below(4u));
    std::vector<est::JcbbSighting> z;
    for (int i = 0; i < n; ++i) {
      est::JcbbSighting s = sight(truth, lm[rng.below(9u)], 0.1f, 0.03f);
      s.range += rng.uniform(-0.1f, 0.1f);
      if (rng.below(5u) == 0) s.bearing = rng.uniform(-3.0f, 3.0f);  // clutter
      z.push_back(s);
    }
    const auto r = jcbb.associate(mu, P, z.data(), n, map, params);
    REQUIRE(r.ok);
    // Exhaustive: every map of sightings into (landmarks or none), injective, individually and jointly gated.
    int best_k = 0;
    double best_d2 = 0.0;
    std::vector<int> a(static_cast<std::size_t>(n), -1);
    int total = 1;
    for (int i = 0; i < n; ++i) total *= 10;
    for (int code = 0; code < total; ++code) {
      int c = code, k = 0;
      bool ok = true;
      for (int i = 0; i < n; ++i, c /= 10) {
        a[static_cast<std::size_t>(i)] = c % 10 - 1;
        if (a[static_cast<std::size_t>(i)] < 0) continue;
        ++k;
        for (int i2 = 0; i2 < i; ++i2) ok = ok && a[static_cast<std::size_t>(i2)] != a[static_cast<std::size_t>(i)];
        std::vector<int> one(static_cast<std::size_t>(n), -1);
        one[static_cast<std::size_t>(i)] = a[static_cast<std::size_t>(i)];
        ok = ok && direct_joint_nis(mu, P, z, map, one) <= static_cast<double>(params.individual_chi2);
      }
      if (!ok || k < best_k) continue;
      const double d2 = direct_joint_nis(mu, P, z, map, a);
      if (d2 > static_cast<double>(params.joint_gate(k))) continue;
      if (k > best_k || d2 < best_d2) best_k = k, best_d2 = d2;
    }
    CHECK(r.paired == best_k);
    CHECK(static_cast<double>(r.joint_nis) == Approx(best_d2).epsilon(2e-3).margin(2e-3));
    if (best_k >= 2) ++nontrivial;
  }
  CHECK(nontrivial > 30);
}

TEST_CASE("jcbb stops at its node cap, says so, and refuses a frame beyond its capacity", "[jcbb]") {
  // Nine posts in a tight cluster and a loose belief: every sighting is compatible with every post.
  std::vector<est::Landmark> lm;
  for (int j = 0; j < 9; ++j) lm.push_back({5.0f + 0.1f * static_cast<float>(j % 3), 0.1f * static_cast<float>(j / 3), 0.0f});
  const est::LandmarkMap map(lm.data(), 9);
  const Eigen::Vector3f mu(0.0f, 0.0f, 0.0f);
  const Eigen::Matrix3f P = Eigen::Vector3f(1.0f, 1.0f, 0.1f).asDiagonal();
  std::vector<est::JcbbSighting> z;
  const float skew[4] = {0.25f, -0.2f, 0.3f, -0.15f};  // range errors: the nearest posts are not the joint best
  for (int i = 0; i < 4; ++i) {
    z.push_back(sight(mu, lm[static_cast<std::size_t>(2 * i)], 0.3f, 0.1f));
    z.back().range += skew[i];
    z.back().bearing -= 0.3f * skew[i];
  }
  est::JointCompatibility<4, 9> jcbb;
  est::JcbbParams params;
  params.max_nodes = 50;
  const auto capped = jcbb.associate(mu, P, z.data(), 4, map, params);
  REQUIRE(capped.ok);
  CHECK(capped.node_cap_hit);
  CHECK(capped.nodes == 50u);
  CHECK(capped.paired == 4);  // depth first, nearest first: a full assignment is among the first found
  params.max_nodes = 100000;
  const auto full = jcbb.associate(mu, P, z.data(), 4, map, params);
  CHECK_FALSE(full.node_cap_hit);
  CHECK(full.nodes > 50u);
  CHECK(full.joint_nis <= capped.joint_nis);
  // Six candidates kept of nine: three dropped per sighting.
  est::JointCompatibility<4, 6> small;
  CHECK(small.associate(mu, P, z.data(), 4, map, params).candidates_dropped == 12u);
  std::vector<est::JcbbSighting> five(5, z[0]);
  const auto over = jcbb.associate(mu, P, five.data(), 5, map, params);
  CHECK(over.too_many);
  CHECK(over.paired == 0);
}
