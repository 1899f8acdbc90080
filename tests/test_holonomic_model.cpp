#include <array>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <iomanip>
#include <vector>

#include "density_check.hpp"
#include "est/motion/holonomic_model.hpp"
#include "statistics.hpp"

using est::HolonomicMotionModel;
using est::HolonomicParams;
using Vec2 = Eigen::Vector2f;

namespace {

double d(float f) { return static_cast<double>(f); }

// Correlated noise: std 0.1 m and 0.05 m, correlation 0.6; B maps a velocity (m/s) over dt = 0.5 s, with a skew.
HolonomicParams params() {
  HolonomicParams p;
  p.B << 0.5f, 0.1f, 0.0f, 0.5f;
  p.Q << 0.01f, 0.003f, 0.003f, 0.0025f;
  return p;
}

std::uint32_t bits(float f) {
  std::uint32_t b = 0;
  std::memcpy(&b, &f, sizeof b);
  return b;
}

}  // namespace

TEST_CASE("zero noise: sample is x + B u exactly", "[holonomic]") {
  HolonomicParams p;  // B = I, Q = 0
  est::Rng rng(5u);
  const Vec2 x = HolonomicMotionModel::sample(Vec2(1.0f, -2.0f), Vec2(0.25f, 0.5f), p, rng);
  CHECK(x(0) == 1.25f);
  CHECK(x(1) == -1.5f);
  p.B << 0.5f, 0.1f, 0.0f, 0.5f;
  const Vec2 y = HolonomicMotionModel::sample(Vec2(1.0f, -2.0f), Vec2(2.0f, 1.0f), p, rng);
  CHECK(d(y(0)) == Approx(1.0 + 1.0 + 0.1).margin(1e-6));
  CHECK(d(y(1)) == Approx(-2.0 + 0.5).margin(1e-6));
}

TEST_CASE("samples have mean B u and covariance Q (200k draws, 5 standard errors)", "[holonomic]") {
  const HolonomicParams p = params();
  est::Rng rng(99u);
  const int n = 200000;
  double s0 = 0, s1 = 0, s00 = 0, s01 = 0, s11 = 0;
  for (int i = 0; i < n; ++i) {
    const Vec2 x = HolonomicMotionModel::sample(Vec2(0.0f, 0.0f), Vec2(2.0f, 1.0f), p, rng);
    const double a = d(x(0)) - 1.1, b = d(x(1)) - 0.5;
    s0 += a;
    s1 += b;
    s00 += a * a;
    s01 += a * b;
    s11 += b * b;
  }
  const double nn = n;
  CHECK(std::fabs(s0 / nn) < 5 * std::sqrt(0.01 / nn));
  CHECK(std::fabs(s1 / nn) < 5 * std::sqrt(0.0025 / nn));
  // standard error of a sample (co)variance of normals: sqrt((q_ij^2 + q_ii q_jj) / n)
  CHECK(std::fabs(s00 / nn - 0.01) < 5 * std::sqrt(2 * 0.01 * 0.01 / nn));
  CHECK(std::fabs(s11 / nn - 0.0025) < 5 * std::sqrt(2 * 0.0025 * 0.0025 / nn));
  CHECK(std::fabs(s01 / nn - 0.003) < 5 * std::sqrt((0.003 * 0.003 + 0.01 * 0.0025) / nn));
}

TEST_CASE("likelihood is the Gaussian density: integrates to one and matches the sampler's histogram",
          "[holonomic]") {
  // 2-D grid over mean +- 7 sigma; the third axis is a dummy of width 1. 40 x 40 sub-cells x 27 points.
  const HolonomicParams p = params();
  const Vec2 x0(0.3f, 0.1f), u(2.0f, 1.0f);
  const est::test::Grid3 g{{1.4 - 0.7, 0.6 - 0.35, 0.0}, {1.4 + 0.7, 0.6 + 0.35, 1.0}, {20, 20, 1}};
  const auto masses = est::test::integrate_cells(g, 2, [&](double a, double b, double) {
    return d(HolonomicMotionModel::likelihood(Vec2(static_cast<float>(a), static_cast<float>(b)), u, x0, p));
  });
  const double mass = est::test::total(masses);
  INFO("mass " << std::setprecision(9) << mass);
  CHECK(std::fabs(mass - 1.0) < 1e-4);  // measured |mass - 1| < 1e-6

  est::Rng rng(77u);
  std::vector<std::array<double, 3>> samples;
  for (int i = 0; i < 200000; ++i) {
    const Vec2 x = HolonomicMotionModel::sample(x0, u, p, rng);
    samples.push_back({d(x(0)), d(x(1)), 0.5});
  }
  const auto r = est::test::goodness_of_fit(g, masses, samples, 0.001);
  INFO("chi2 " << r.chi2 << " dof " << r.dof << " critical " << r.critical << " TV " << r.total_variation);
  CHECK(r.outside == 0u);
  CHECK(r.dof > 50);
  CHECK(r.chi2 < r.critical);
  CHECK(r.total_variation < 0.02);

  // And at a point, against the closed form in double.
  const double r0 = 1.5 - 1.4, r1 = 0.55 - 0.6;
  const double det = 0.01 * 0.0025 - 0.003 * 0.003;
  const double q = (0.0025 * r0 * r0 - 2 * 0.003 * r0 * r1 + 0.01 * r1 * r1) / det;
  const double expect = std::exp(-0.5 * q) / (2 * 3.14159265358979323846 * std::sqrt(det));
  CHECK(d(HolonomicMotionModel::likelihood(Vec2(1.5f, 0.55f), u, x0, p)) == Approx(expect).epsilon(1e-5));
}

TEST_CASE("Jacobians: G = I, V = B (central differences), V M V^T = Q", "[holonomic]") {
  const HolonomicParams p = params();
  const Vec2 x0(0.3f, 0.1f), u(2.0f, 1.0f);
  const auto j = HolonomicMotionModel::jacobians(x0, u, p);
  CHECK(j.G.isApprox(Eigen::Matrix2f::Identity()));
  for (int k = 0; k < 2; ++k) {
    Vec2 e = Vec2::Zero();
    e(k) = 0.01f;
    const Vec2 dv = (HolonomicMotionModel::predict(x0, u + e, p) - HolonomicMotionModel::predict(x0, u - e, p)) / 0.02f;
    const Vec2 dx = (HolonomicMotionModel::predict(x0 + e, u, p) - HolonomicMotionModel::predict(x0 - e, u, p)) / 0.02f;
    for (int r = 0; r < 2; ++r) {
      CHECK(d(j.V(r, k)) == Approx(d(dv(r))).margin(1e-5));
      CHECK(d(j.G(r, k)) == Approx(d(dx(r))).margin(1e-5));
    }
  }
  const Eigen::Matrix2f back = j.V * j.M * j.V.transpose();
  for (int r = 0; r < 2; ++r)
    for (int k = 0; k < 2; ++k) CHECK(d(back(r, k)) == Approx(d(p.Q(r, k))).margin(1e-8));
}

TEST_CASE("same seed gives the same bits; different seeds differ", "[holonomic]") {
  const HolonomicParams p = params();
  const auto run = [&](std::uint64_t seed) {
    est::Rng rng(seed);
    std::vector<std::uint32_t> out;
    Vec2 x = Vec2::Zero();
    for (int i = 0; i < 1000; ++i) {
      x = HolonomicMotionModel::sample(x, Vec2(0.1f, -0.2f), p, rng);
      out.push_back(bits(x(0)));
      out.push_back(bits(x(1)));
      out.push_back(bits(HolonomicMotionModel::log_likelihood(x, Vec2(0.1f, -0.2f), Vec2::Zero(), p)));
    }
    return out;
  };
  CHECK(run(7u) == run(7u));
  CHECK(run(7u) != run(8u));
}

TEST_CASE("check rejects non-finite controls and bad B or Q with the right status", "[holonomic]") {
  using est::MotionStatus;
  const float nan = std::nanf("");
  const HolonomicParams ok = params();
  CHECK(HolonomicMotionModel::check(Vec2(1.0f, 2.0f), ok) == MotionStatus::ok);
  CHECK(HolonomicMotionModel::check(Vec2(nan, 2.0f), ok) == MotionStatus::rejected_nonfinite);
  CHECK(HolonomicMotionModel::check(Vec2(2e6f, 2.0f), ok) == MotionStatus::rejected_range);
  HolonomicParams p = ok;
  p.Q(1, 0) = INFINITY;
  CHECK(HolonomicMotionModel::check(Vec2(1.0f, 2.0f), p) == MotionStatus::rejected_nonfinite);
  p = ok;
  p.B << 1.0f, 2.0f, 2.0f, 4.0f;  // singular
  CHECK(HolonomicMotionModel::check(Vec2(1.0f, 2.0f), p) == MotionStatus::rejected_range);
  p = ok;
  p.Q(0, 0) = -0.01f;  // negative variance
  CHECK(HolonomicMotionModel::check(Vec2(1.0f, 2.0f), p) == MotionStatus::rejected_range);
  p = ok;
  p.Q(0, 1) = 0.004f;  // not symmetric
  CHECK(HolonomicMotionModel::check(Vec2(1.0f, 2.0f), p) == MotionStatus::rejected_range);
  p = ok;
  p.Q << 0.01f, 0.01f, 0.01f, 0.0025f;  // correlation 2: indefinite
  CHECK(HolonomicMotionModel::check(Vec2(1.0f, 2.0f), p) == MotionStatus::rejected_range);
  p = ok;
  p.Q << 0.01f, 0.005f, 0.005f, 0.0025f;  // correlation 1: semi-definite, accepted
  CHECK(HolonomicMotionModel::check(Vec2(1.0f, 2.0f), p) == MotionStatus::ok);
}

TEST_CASE("likelihood stays finite for singular Q and non-finite states", "[holonomic]") {
  HolonomicParams p;  // Q = 0: point mass
  const Vec2 x0(1.0f, 1.0f), u(0.5f, 0.5f);
  const float at_mean = HolonomicMotionModel::log_likelihood(Vec2(1.5f, 1.5f), u, x0, p);
  CHECK(std::isfinite(at_mean));
  CHECK(at_mean <= est::motion_density::kMaxLogDensity);
  CHECK(HolonomicMotionModel::likelihood(Vec2(1.6f, 1.5f), u, x0, p) == 0.0f);
  p.Q << 0.01f, 0.005f, 0.005f, 0.0025f;  // rank 1
  CHECK(std::isfinite(HolonomicMotionModel::likelihood(Vec2(1.6f, 1.55f), u, x0, p)));
  CHECK(HolonomicMotionModel::likelihood(Vec2(std::nanf(""), 1.5f), u, x0, p) == 0.0f);
  CHECK(HolonomicMotionModel::likelihood(Vec2(3e38f, -3e38f), u, x0, p) == 0.0f);
}
