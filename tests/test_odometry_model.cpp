#include <algorithm>
#include <array>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <iomanip>
#include <vector>

#include "density_check.hpp"
#include "est/motion/odometry_model.hpp"
#include "statistics.hpp"

using est::OdometryControl;
using est::OdometryMotionModel;
using est::OdometryParams;
using est::Pose2;

namespace {

constexpr double kPi = 3.14159265358979323846;

double wrap(double a) { return std::remainder(a, 2.0 * kPi); }
double d(float f) { return static_cast<double>(f); }

OdometryParams noisy() {
  OdometryParams p;
  p.a1 = 0.02f;
  p.a2 = 0.01f;
  p.a3 = 0.01f;
  p.a4 = 0.005f;
  return p;
}

// Odometry control whose increment is (rot1, trans, rot2), read in an odometry frame offset from the world.
OdometryControl control(float rot1, float trans, float rot2) {
  const Pose2 a{10.0f, 5.0f, 1.0f};
  const Pose2 b{a.x + trans * std::cos(a.theta + rot1), a.y + trans * std::sin(a.theta + rot1),
                static_cast<float>(wrap(d(a.theta) + d(rot1) + d(rot2)))};
  return {a, b};
}

std::uint32_t bits(float f) {
  std::uint32_t b = 0;
  std::memcpy(&b, &f, sizeof b);
  return b;
}

}  // namespace

TEST_CASE("zero noise: sample equals the odometry increment applied to the pose", "[odometry]") {
  const OdometryParams p{};
  est::Rng rng(3u);
  SECTION("hand computed: odometry (0,0,0) -> (1,1,pi/2) from (2,3,pi/2) ends at (1,4,pi)") {
    // rot1 = atan2(1, 1) = pi/4, trans = sqrt(2), rot2 = pi/2 - pi/4; x' = 2 + sqrt(2) cos(3pi/4) = 1, y' = 4.
    const OdometryControl u{{0.0f, 0.0f, 0.0f}, {1.0f, 1.0f, est::kHalfPi}};
    const auto inc = est::odometry_increment(u, p);
    CHECK(inc.rot1 == Approx(kPi / 4).margin(1e-6));
    CHECK(inc.trans == Approx(std::sqrt(2.0)).margin(1e-6));
    CHECK(inc.rot2 == Approx(kPi / 4).margin(1e-6));
    const Pose2 x = OdometryMotionModel::sample({2.0f, 3.0f, est::kHalfPi}, u, p, rng);
    CHECK(x.x == Approx(1.0).margin(1e-6));
    CHECK(x.y == Approx(4.0).margin(1e-6));
    CHECK(std::fabs(std::fabs(d(x.theta)) - kPi) < 1e-6);  // pi, wrapped to (-pi, pi]
  }
  SECTION("reversing: the robot backs up along its heading (the increment (0, -1, 0), not (pi, 1, -pi))") {
    const OdometryControl u{{0.0f, 0.0f, 0.0f}, {-1.0f, 0.0f, 0.0f}};
    const Pose2 x = OdometryMotionModel::sample({1.0f, 1.0f, est::kHalfPi}, u, p, rng);
    CHECK(x.x == Approx(1.0).margin(1e-6));
    CHECK(x.y == Approx(0.0).margin(1e-6));
    CHECK(x.theta == Approx(kPi / 2).margin(1e-6));
  }
  SECTION("pure rotation: rot1 = rot2 = half the turn, the position stays") {
    const OdometryControl u{{5.0f, 5.0f, 3.0f}, {5.0f, 5.0f, -2.9f}};  // turn wraps: -2.9 - 3 + 2 pi = 0.383
    const auto inc = est::odometry_increment(u, p);
    const double turn = wrap(-2.9 - 3.0);
    CHECK(inc.rot1 == Approx(turn / 2).margin(1e-6));
    CHECK(inc.rot2 == Approx(turn / 2).margin(1e-6));
    CHECK(inc.trans == 0.0f);
    const Pose2 x = OdometryMotionModel::sample({1.0f, 2.0f, 0.1f}, u, p, rng);
    CHECK(x.x == 1.0f);
    CHECK(x.y == 2.0f);
    CHECK(x.theta == Approx(0.1 + turn).margin(1e-6));
  }
  SECTION("a translation below min_translation keeps its length and takes the half-turn direction") {
    const OdometryControl u{{0.0f, 0.0f, 0.0f}, {0.0f, -5e-5f, 0.8f}};
    const auto inc = est::odometry_increment(u, p);
    CHECK(inc.rot1 == Approx(0.4).margin(1e-6));
    CHECK(inc.trans == Approx(5e-5).epsilon(1e-6));
    OdometryParams q = p;
    q.min_translation = 1e-5f;  // now the direction is trusted: straight down, rot1 = -pi/2
    CHECK(est::odometry_increment(u, q).rot1 == Approx(-kPi / 2).margin(1e-6));
  }
  SECTION("the odometry frame does not matter, only the increment; sample with zero noise is predict") {
    const OdometryControl u = control(0.3f, 0.8f, -0.2f);
    const Pose2 x0{0.5f, -0.3f, 0.2f};
    const Pose2 x = OdometryMotionModel::sample(x0, u, p, rng);
    CHECK(x.x == Approx(0.5 + 0.8 * std::cos(0.5)).margin(2e-6));
    CHECK(x.y == Approx(-0.3 + 0.8 * std::sin(0.5)).margin(2e-6));
    CHECK(x.theta == Approx(0.3).margin(2e-6));
    const Pose2 y = OdometryMotionModel::predict(x0, u, p);
    CHECK(bits(x.x) == bits(y.x));
    CHECK(bits(x.y) == bits(y.y));
    CHECK(bits(x.theta) == bits(y.theta));
  }
}

TEST_CASE("reversing is read as the robot's own motion: trans < 0, rot1 and rot2 the small rotations", "[odometry]") {
  const OdometryParams p = noisy();
  SECTION("backing up 0.1 m straight: (0, -0.1, 0), not (pi, 0.1, -pi)") {
    const Pose2 a{2.0f, 1.0f, 0.7f};
    const OdometryControl u{a, {a.x - 0.1f * std::cos(a.theta), a.y - 0.1f * std::sin(a.theta), a.theta}};
    const auto inc = est::odometry_increment(u, p);
    CHECK(inc.rot1 == Approx(0.0).margin(1e-5));
    CHECK(inc.trans == Approx(-0.1).epsilon(1e-5));
    CHECK(inc.rot2 == Approx(0.0).margin(1e-5));
  }
  SECTION("a chord behind the robot on either side: rot1 shifted by pi into [-pi/2, pi/2], the turn kept") {
    for (const float r1 : {0.4f, -1.2f, 1.5f}) {
      const OdometryControl u = control(r1, -0.6f, -0.3f);
      const auto inc = est::odometry_increment(u, p);
      INFO("rot1 " << r1);
      CHECK(inc.rot1 == Approx(r1).margin(1e-5));
      CHECK(inc.trans == Approx(-0.6).epsilon(1e-6));
      CHECK(inc.rot2 == Approx(-0.3).margin(1e-5));
    }
  }
  SECTION("|rot1| = pi/2 exactly (sideways) stays forward; just past it, reverse") {
    const OdometryControl side{{0.0f, 0.0f, 0.0f}, {0.0f, 0.5f, 0.0f}};
    CHECK(est::odometry_increment(side, p).trans == Approx(0.5).epsilon(1e-6));
    CHECK(est::odometry_increment(side, p).rot1 == Approx(kPi / 2).margin(1e-6));
    const OdometryControl past{{0.0f, 0.0f, 0.0f}, {-1e-3f, 0.5f, 0.0f}};
    CHECK(est::odometry_increment(past, p).trans == Approx(-0.5).epsilon(1e-5));
    CHECK(est::odometry_increment(past, p).rot1 == Approx(-kPi / 2 + 2e-3).margin(1e-5));
  }
}

TEST_CASE("a robot backing up 0.1 m straight keeps the heading spread of its small rotations, not a scatter over pi",
          "[odometry]") {
  // Increment (0, -0.1, 0): theta' - theta = rot1_hat + rot2_hat with var(rot1 noise) = var(rot2 noise) =
  // a1 0^2 + a2 0.1^2 = 1e-4, so the heading's sd is sqrt(2e-4) = 0.01414 rad; the travel along the start heading is
  // trans_hat cos(rot1_hat): mean -0.1 (1 - 5e-5), sd sqrt(a3 0.1^2 + a4 0) = 0.01 m. Read forward as
  // (pi, 0.1, -pi) the heading's sd would be sqrt(2 (a1 pi^2 + a2 0.1^2)) = 0.63 rad and trans noise's 0.31 m.
  // Tolerances: 5 standard errors of the sample mean and variance at n = 100k (2.2 % on a variance).
  const OdometryParams p = noisy();
  const Pose2 a{2.0f, 1.0f, 0.7f};
  const OdometryControl u{a, {a.x - 0.1f * std::cos(a.theta), a.y - 0.1f * std::sin(a.theta), a.theta}};
  const Pose2 x0{-3.0f, 4.0f, 0.3f};
  constexpr std::size_t n = 100000;
  est::Rng rng(77u);
  std::vector<double> heading, along;
  heading.reserve(n);
  along.reserve(n);
  for (std::size_t i = 0; i < n; ++i) {
    const Pose2 x = OdometryMotionModel::sample(x0, u, p, rng);
    heading.push_back(wrap(d(x.theta) - d(x0.theta)));
    along.push_back((d(x.x) - d(x0.x)) * std::cos(d(x0.theta)) + (d(x.y) - d(x0.y)) * std::sin(d(x0.theta)));
  }
  const double var_heading = 2.0 * 0.01 * 0.1 * 0.1, var_along = 0.01 * 0.1 * 0.1;
  const auto h = est::test::moments(heading), t = est::test::moments(along);
  INFO("heading mean " << h.mean << " sd " << std::sqrt(h.variance) << "; along mean " << t.mean << " sd "
                       << std::sqrt(t.variance));
  CHECK(std::fabs(h.mean) < 5.0 * est::test::mean_standard_error(var_heading, n));
  CHECK(std::fabs(h.variance - var_heading) < 5.0 * est::test::variance_standard_error(var_heading, 0.0, n));
  double worst = 0.0;
  for (double e : heading) worst = std::max(worst, std::fabs(e));
  CHECK(worst < 8.0 * std::sqrt(var_heading));
  CHECK(std::fabs(t.mean - (-0.1 * (1.0 - 0.5 * 1e-4))) < 5.0 * est::test::mean_standard_error(var_along, n));
  CHECK(std::fabs(t.variance - var_along) < 5.0 * est::test::variance_standard_error(var_along, 0.0, n));
}

namespace {

// Samples as (x, y, theta), or in the chord chart (signed chord from x0, its direction relative to x0's heading
// folded into (-pi/2, pi/2], theta) where the density gains the polar factor |chord|.
std::vector<std::array<double, 3>> draw(const Pose2& x0, const OdometryControl& u, const OdometryParams& p, int n,
                                        bool chord_chart) {
  est::Rng rng(424242u);
  std::vector<std::array<double, 3>> out;
  out.reserve(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) {
    const Pose2 x = OdometryMotionModel::sample(x0, u, p, rng);
    if (!chord_chart) {
      out.push_back({d(x.x), d(x.y), d(x.theta)});
      continue;
    }
    const double dx = d(x.x) - d(x0.x), dy = d(x.y) - d(x0.y);
    double psi = wrap(std::atan2(dy, dx) - d(x0.theta));
    double c = std::hypot(dx, dy);
    if (psi > kPi / 2) {
      psi -= kPi;
      c = -c;
    } else if (psi <= -kPi / 2) {
      psi += kPi;
      c = -c;
    }
    out.push_back({c, psi, d(x.theta)});
  }
  return out;
}

struct Case {
  const char* name;
  Pose2 x0;
  OdometryControl u;
  OdometryParams p;
  est::test::Grid3 grid;
  bool chord_chart;
};

std::vector<Case> cases() {
  OdometryParams wide = noisy();
  wide.a3 = 0.5f;
  return {
      {"rot1 = 0.3, trans = 0.8, rot2 = 0.3",
       {0.5f, -0.3f, 0.2f},
       control(0.3f, 0.8f, 0.3f),
       noisy(),
       {{0.5 + 0.8 * std::cos(0.5) - 0.6, -0.3 + 0.8 * std::sin(0.5) - 0.6, 0.8 - 0.9},
        {0.5 + 0.8 * std::cos(0.5) + 0.6, -0.3 + 0.8 * std::sin(0.5) + 0.6, 0.8 + 0.9},
        {12, 12, 10}},
       false},
      // at the origin: elsewhere a |trans_hat| below the start's float spacing rounds to a random direction
      {"pure rotation by 1.2 rad (singular at the start point, trans_hat of both signs)",
       {0.0f, 0.0f, 0.2f},
       {{2.0f, 2.0f, 0.0f}, {2.0f, 2.0f, 1.2f}},
       noisy(),
       {{-0.4, 0.0, 1.4 - 0.85}, {0.4, 1.2, 1.4 + 0.85}, {12, 12, 10}},
       true},
      {"short step trans = 0.05 with trans noise 0.037: 9 % of samples land behind (second preimage)",
       {0.0f, 0.0f, 0.0f},
       control(0.1f, 0.05f, -0.1f),
       wide,
       {{-0.25, 0.1 - 0.12, -0.15}, {0.3, 0.1 + 0.12, 0.15}, {12, 12, 10}},
       true},
      // the mirror images of the first and the third: the same boxes reflected through x0 along the travel
      {"reversing: rot1 = 0.3, trans = -0.8, rot2 = 0.3",
       {0.5f, -0.3f, 0.2f},
       control(0.3f, -0.8f, 0.3f),
       noisy(),
       {{0.5 - 0.8 * std::cos(0.5) - 0.6, -0.3 - 0.8 * std::sin(0.5) - 0.6, 0.8 - 0.9},
        {0.5 - 0.8 * std::cos(0.5) + 0.6, -0.3 - 0.8 * std::sin(0.5) + 0.6, 0.8 + 0.9},
        {12, 12, 10}},
       false},
      {"short reverse step trans = -0.05 with trans noise 0.037: 9 % of samples land ahead (second preimage)",
       {0.0f, 0.0f, 0.0f},
       control(0.1f, -0.05f, -0.1f),
       wide,
       {{-0.3, 0.1 - 0.12, -0.15}, {0.25, 0.1 + 0.12, 0.15}, {12, 12, 10}},
       true},
  };
}

std::vector<double> cell_masses(const Case& c, int sub) {
  return est::test::integrate_cells(c.grid, sub, [&](double a, double b, double t) {
    if (!c.chord_chart)
      return d(OdometryMotionModel::likelihood(
          {static_cast<float>(a), static_cast<float>(b), static_cast<float>(t)}, c.u, c.x0, c.p));
    const double ang = d(c.x0.theta) + b;
    const Pose2 x{static_cast<float>(d(c.x0.x) + a * std::cos(ang)), static_cast<float>(d(c.x0.y) + a * std::sin(ang)),
                  static_cast<float>(t)};
    return std::fabs(a) * d(OdometryMotionModel::likelihood(x, c.u, c.x0, c.p));
  });
}

}  // namespace

TEST_CASE("likelihood integrates to one over the pose (table 5.5 with 1/rho and both preimages)", "[odometry]") {
  // 36 x 36 x 30 sub-cells x 27 Gauss points = 1.05e6 evaluations per case, boxes of >= 7 sigma (no sample of 200k
  // outside, checked below). Measured |mass - 1| <= 2e-6. Table 5.5's forward preimage alone would give 0.91 in the
  // third case (the 9 % of negative trans_hat). Reversing, an increment read forward as (~pi, 0.8, ~-pi) would put
  // most of the mass outside the fourth and fifth boxes (heading sd 0.6 rad).
  for (const Case& c : cases()) {
    INFO(c.name);
    const double mass = est::test::total(cell_masses(c, 3));
    INFO("mass " << std::setprecision(9) << mass);
    CHECK(std::fabs(mass - 1.0) < 1e-4);
  }
}

TEST_CASE("sample and likelihood agree: chi-square over 1440 cells at 200k samples, alpha = 0.001", "[odometry]") {
  for (const Case& c : cases()) {
    INFO(c.name);
    const auto masses = cell_masses(c, 3);
    const auto samples = draw(c.x0, c.u, c.p, 200000, c.chord_chart);
    const est::test::FitResult r = est::test::goodness_of_fit(c.grid, masses, samples, 0.001);
    INFO("chi2 " << r.chi2 << " dof " << r.dof << " critical " << r.critical << " TV " << r.total_variation
                 << " outside " << r.outside);
    CHECK(r.outside == 0u);
    CHECK(r.dof > 50);
    CHECK(r.chi2 < r.critical);
    CHECK(r.total_variation < 0.02);
  }
}

TEST_CASE("the book's unnormalized product differs from the density by rho where the second preimage is negligible",
          "[odometry]") {
  const OdometryParams p = noisy();
  const Pose2 x0{0.0f, 0.0f, 0.0f};
  // forward, and reversing with lines 5-7 reading the pose pair as a reverse translation too
  for (const float sign : {1.0f, -1.0f}) {
    const OdometryControl u = control(0.3f, sign * 0.8f, 0.3f);
    const Pose2 x{sign * 0.7f, sign * 0.25f, 0.55f};
    const double rho = std::hypot(0.7, 0.25);
    INFO("trans " << sign * 0.8f);
    const double ratio =
        d(est::motion_model_odometry_unnormalized(x, u, x0, p)) / d(est::motion_model_odometry(x, u, x0, p));
    CHECK(ratio == Approx(rho).epsilon(1e-4));
    CHECK(std::log(d(OdometryMotionModel::likelihood(x, u, x0, p))) ==
          Approx(d(OdometryMotionModel::log_likelihood(x, u, x0, p))).margin(1e-5));
  }
}

TEST_CASE("Jacobians G and V (w.r.t. rot1, trans, rot2) match central differences; M is the book's variances",
          "[odometry]") {
  // Reference g in double; central differences with step 1e-6 (error < 1e-9); tolerance 1e-5 (1 + |entry|).
  const auto g = [](const double s[3], const double inc[3]) {
    return std::array<double, 3>{s[0] + inc[1] * std::cos(s[2] + inc[0]), s[1] + inc[1] * std::sin(s[2] + inc[0]),
                                 s[2] + inc[0] + inc[2]};
  };
  // Reversing (trans = -0.5, and odometry rot1 = -2.0 forward, which is rot1 = -2 + pi backwards): the increment is
  // (rot1 in [-pi/2, pi/2], trans < 0, rot2), and G, V, M are taken there.
  const OdometryParams p = noisy();
  const Pose2 x0{0.4f, -1.0f, 2.9f};
  const float rot1s[] = {0.3f, -2.0f, 0.0f};
  for (float r1 : rot1s)
    for (float tr : {0.8f, -0.5f, 0.0f}) {
      const OdometryControl u = tr != 0.0f ? control(r1, tr, -0.4f) : OdometryControl{{0, 0, 0}, {0, 0, 0.6f}};
      const auto inc = est::odometry_increment(u, p);
      const auto j = OdometryMotionModel::jacobians(x0, u, p);
      const double s[3] = {d(x0.x), d(x0.y), d(x0.theta)};
      const double q[3] = {d(inc.rot1), d(inc.trans), d(inc.rot2)};
      INFO("rot1 " << r1 << " trans " << tr << " increment " << q[0] << " " << q[1] << " " << q[2]);
      CHECK(std::fabs(q[0]) <= kPi / 2 + 1e-6);
      if (tr != 0.0f) {
        const bool behind = std::fabs(d(r1)) > kPi / 2 ? tr > 0.0f : tr < 0.0f;
        CHECK((q[1] < 0.0) == behind);
        CHECK(std::fabs(q[1]) == Approx(std::fabs(tr)).epsilon(1e-5));
      }
      for (int k = 0; k < 3; ++k) {
        double sa[3] = {s[0], s[1], s[2]}, sb[3] = {s[0], s[1], s[2]};
        double qa[3] = {q[0], q[1], q[2]}, qb[3] = {q[0], q[1], q[2]};
        sa[k] += 1e-6;
        sb[k] -= 1e-6;
        qa[k] += 1e-6;
        qb[k] -= 1e-6;
        const auto gsa = g(sa, q), gsb = g(sb, q), gqa = g(s, qa), gqb = g(s, qb);
        for (std::size_t r = 0; r < 3; ++r) {
          const double G = (gsa[r] - gsb[r]) / 2e-6, V = (gqa[r] - gqb[r]) / 2e-6;
          const int ri = static_cast<int>(r);
          CHECK(d(j.G(ri, k)) == Approx(G).margin(1e-5 * (1 + std::fabs(G))));
          CHECK(d(j.V(ri, k)) == Approx(V).margin(1e-5 * (1 + std::fabs(V))));
        }
      }
      CHECK(d(j.M(0, 0)) == Approx(0.02 * q[0] * q[0] + 0.01 * q[1] * q[1]).margin(1e-7));
      CHECK(d(j.M(1, 1)) == Approx(0.01 * q[1] * q[1] + 0.005 * (q[0] * q[0] + q[2] * q[2])).margin(1e-7));
      CHECK(d(j.M(2, 2)) == Approx(0.02 * q[2] * q[2] + 0.01 * q[1] * q[1]).margin(1e-7));
      CHECK(j.M(0, 1) == 0.0f);
    }
}

TEST_CASE("same seed gives the same bits; different seeds differ", "[odometry]") {
  const OdometryParams p = noisy();
  const OdometryControl u = control(0.1f, 0.05f, 0.02f);
  const auto run = [&](std::uint64_t seed) {
    est::Rng rng(seed);
    std::vector<std::uint32_t> out;
    Pose2 x{};
    for (int i = 0; i < 1000; ++i) {
      x = OdometryMotionModel::sample(x, u, p, rng);
      out.push_back(bits(x.x));
      out.push_back(bits(x.y));
      out.push_back(bits(x.theta));
      out.push_back(bits(OdometryMotionModel::log_likelihood(x, u, Pose2{}, p)));
    }
    return out;
  };
  CHECK(run(7u) == run(7u));
  CHECK(run(7u) != run(8u));
}

TEST_CASE("check rejects non-finite and out-of-range inputs with the right status", "[odometry]") {
  using est::MotionStatus;
  const float nan = std::nanf("");
  const OdometryControl u = control(0.1f, 0.5f, 0.0f);
  CHECK(OdometryMotionModel::check(u, noisy()) == MotionStatus::ok);
  OdometryControl v = u;
  v.odom.theta = nan;
  CHECK(OdometryMotionModel::check(v, noisy()) == MotionStatus::rejected_nonfinite);
  v = u;
  v.odom_prev.x = INFINITY;
  CHECK(OdometryMotionModel::check(v, noisy()) == MotionStatus::rejected_nonfinite);
  v = u;
  v.odom.y = 2e7f;
  CHECK(OdometryMotionModel::check(v, noisy()) == MotionStatus::rejected_range);
  OdometryParams p = noisy();
  p.a4 = nan;
  CHECK(OdometryMotionModel::check(u, p) == MotionStatus::rejected_nonfinite);
  p = noisy();
  p.a1 = -0.1f;
  CHECK(OdometryMotionModel::check(u, p) == MotionStatus::rejected_range);
  p = noisy();
  p.min_translation = -1e-3f;
  CHECK(OdometryMotionModel::check(u, p) == MotionStatus::rejected_range);
  p.min_translation = 2.0f;
  CHECK(OdometryMotionModel::check(u, p) == MotionStatus::rejected_range);
}

TEST_CASE("likelihood stays finite at its singular points and for far or non-finite states", "[odometry]") {
  const float nan = std::nanf("");
  const Pose2 x0{1.0f, 1.0f, 0.0f};
  const OdometryParams zero{};
  const OdometryControl still{{3.0f, 3.0f, 0.0f}, {3.0f, 3.0f, 0.0f}};
  const OdometryControl turn{{3.0f, 3.0f, 0.0f}, {3.0f, 3.0f, 1.0f}};
  const OdometryControl step = control(0.2f, 1.0f, 0.0f);
  struct Probe {
    Pose2 x;
    OdometryControl u;
    OdometryParams p;
  };
  const Probe probes[] = {
      {x0, turn, noisy()},                                              // on the start point
      {x0, still, zero},                                                // stationary, zero noise: point mass
      {OdometryMotionModel::predict(x0, step, zero), step, zero},       // zero noise, on the mean
      {{3e38f, -3e38f, 1.0f}, step, noisy()},                           // far: the chord overflows
      {{nan, 1.0f, 0.0f}, step, noisy()},
  };
  for (const Probe& pr : probes) {
    REQUIRE(est::usable(OdometryMotionModel::check(pr.u, pr.p)));
    const float l = OdometryMotionModel::likelihood(pr.x, pr.u, x0, pr.p);
    const float ll = OdometryMotionModel::log_likelihood(pr.x, pr.u, x0, pr.p);
    CHECK(std::isfinite(l));
    CHECK(l >= 0.0f);
    CHECK(std::isfinite(ll));
    CHECK(ll >= est::motion_density::kLogZero);
    CHECK(ll <= est::motion_density::kMaxLogDensity);
  }
  CHECK(OdometryMotionModel::likelihood({nan, 1.0f, 0.0f}, step, x0, noisy()) == 0.0f);
  CHECK(OdometryMotionModel::likelihood({3e38f, -3e38f, 1.0f}, step, x0, noisy()) == 0.0f);
}
