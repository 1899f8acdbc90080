#include <array>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <iomanip>
#include <vector>

#include "density_check.hpp"
#include "est/motion/velocity_model.hpp"
#include "statistics.hpp"

using est::Pose2;
using est::VelocityControl;
using est::VelocityMotionModel;
using est::VelocityParams;

namespace {

constexpr double kPi = 3.14159265358979323846;

// Thrun eq. 5.9 as printed, in double; where |w dt| < 1e-2 its v / w cancels digits even in double (1e-9 at
// w = 1e-7, which finite differences would blow up), so there the same arc in chord form with the sinc series.
std::array<double, 3> book_arc(double x, double y, double th, double v, double w, double dt) {
  if (std::fabs(w * dt) < 1e-2) {
    const double h = 0.5 * w * dt;
    const double chord = v * dt * (1.0 - h * h / 6.0 + h * h * h * h / 120.0);
    return {x + chord * std::cos(th + h), y + chord * std::sin(th + h), th + w * dt};
  }
  const double r = v / w;
  return {x - r * std::sin(th) + r * std::sin(th + w * dt), y + r * std::cos(th) - r * std::cos(th + w * dt),
          th + w * dt};
}

double wrap(double a) { return std::remainder(a, 2.0 * kPi); }

VelocityParams noisy(float dt) {
  VelocityParams p;
  p.a1 = 0.01f;
  p.a2 = 0.002f;
  p.a3 = 0.004f;
  p.a4 = 0.004f;
  p.a5 = 0.001f;
  p.a6 = 0.001f;
  p.dt = dt;
  return p;
}

std::uint32_t bits(float f) {
  std::uint32_t b = 0;
  std::memcpy(&b, &f, sizeof b);
  return b;
}

}  // namespace

TEST_CASE("zero noise: sample equals exact kinematics", "[velocity]") {
  const VelocityParams p{};  // all a_i = 0
  est::Rng rng(1u);
  SECTION("quarter circle: v = 1, w = pi/2, dt = 1 from the origin ends at (2/pi, 2/pi, pi/2)") {
    VelocityParams q = p;
    q.dt = 1.0f;
    const Pose2 x = VelocityMotionModel::sample({}, {1.0f, est::kHalfPi}, q, rng);
    CHECK(x.x == Approx(2.0 / kPi).margin(1e-6));
    CHECK(x.y == Approx(2.0 / kPi).margin(1e-6));
    CHECK(x.theta == Approx(kPi / 2.0).margin(1e-6));
  }
  SECTION("backwards, clockwise, from a general pose: eq. 5.9 in double") {
    VelocityParams q = p;
    q.dt = 0.25f;
    const Pose2 x0{1.0f, -2.0f, 0.3f};
    const Pose2 x = VelocityMotionModel::sample(x0, {-0.7f, -2.1f}, q, rng);
    const auto r = book_arc(1.0, -2.0, double(0.3f), double(-0.7f), double(-2.1f), 0.25);
    CHECK(x.x == Approx(r[0]).margin(1e-6));
    CHECK(x.y == Approx(r[1]).margin(1e-6));
    CHECK(x.theta == Approx(wrap(r[2])).margin(1e-6));
  }
  SECTION("half a turn and more: the heading wraps to (-pi, pi]") {
    VelocityParams q = p;
    q.dt = 1.0f;
    const Pose2 x = VelocityMotionModel::sample({0.0f, 0.0f, 2.0f}, {0.5f, 3.0f}, q, rng);
    const auto r = book_arc(0.0, 0.0, 2.0, 0.5, 3.0, 1.0);
    CHECK(x.x == Approx(r[0]).margin(1e-6));
    CHECK(x.y == Approx(r[1]).margin(1e-6));
    CHECK(x.theta == Approx(wrap(r[2])).margin(1e-6));
    CHECK(x.theta <= est::kPi);
    CHECK(x.theta > -est::kPi);
  }
  SECTION("straight line at w = 0, and w = 1e-7 continuous with it") {
    VelocityParams q = p;
    q.dt = 0.5f;
    const Pose2 x0{0.5f, 0.25f, 0.3f};
    const Pose2 s = VelocityMotionModel::sample(x0, {2.0f, 0.0f}, q, rng);
    CHECK(s.x == Approx(0.5 + std::cos(0.3)).margin(1e-6));
    CHECK(s.y == Approx(0.25 + std::sin(0.3)).margin(1e-6));
    CHECK(s.theta == 0.3f);
    for (float w : {1e-7f, -1e-7f, 1e-5f}) {
      const Pose2 t = VelocityMotionModel::sample(x0, {2.0f, w}, q, rng);
      const auto r = book_arc(0.5, 0.25, double(0.3f), 2.0, double(w), 0.5);  // double: exact enough at r = v / w = 2e7
      CHECK(t.x == Approx(r[0]).margin(1e-6));
      CHECK(t.y == Approx(r[1]).margin(1e-6));
      CHECK(t.theta == Approx(r[2]).margin(1e-6));
      CHECK(std::fabs(double(t.x) - double(s.x)) < 2e-6 + 0.5 * std::fabs(double(w)));
    }
  }
  SECTION("sample with zero noise is predict, bit for bit") {
    VelocityParams q = p;
    q.dt = 0.1f;
    for (float w : {0.0f, 1e-7f, 0.3f, -4.0f}) {
      const Pose2 x0{3.0f, 1.0f, -2.5f};
      const Pose2 a = VelocityMotionModel::sample(x0, {1.5f, w}, q, rng);
      const Pose2 b = VelocityMotionModel::predict(x0, {1.5f, w}, q);
      CHECK(bits(a.x) == bits(b.x));
      CHECK(bits(a.y) == bits(b.y));
      CHECK(bits(a.theta) == bits(b.theta));
    }
  }
}

TEST_CASE("the inverse of table 5.1 recovers the controls that produced a pose, straight and backwards too",
          "[velocity]") {
  const VelocityParams p = noisy(0.5f);
  const Pose2 x0{1.0f, 2.0f, -0.8f};
  const float vs[] = {1.0f, -0.6f, 2.0f};
  const float ws[] = {0.0f, 1e-7f, -1e-4f, 0.8f, -2.5f};
  const float gs[] = {0.0f, 0.2f};
  for (float v : vs)
    for (float w : ws)
      for (float g : gs) {
        const Pose2 x = est::velocity_arc_end(x0, v, w, g, p.dt);
        const est::VelocityPreimage q = est::velocity_preimage(x, {v, w}, x0, p);
        INFO("v " << v << " w " << w << " gamma " << g);
        CHECK(q.v_hat == Approx(v).margin(2e-6));
        CHECK(q.w_hat == Approx(w).margin(2e-5));  // 2 h / dt: float rounding of atan2 near 0, divided by dt
        CHECK(q.gamma_hat == Approx(g).margin(2e-5));
        CHECK_FALSE(q.on_start);
        // |det| = |v| dt^4 sinc(w dt / 2)^2 / 2 (straight limit |v| dt^4 / 2)
        const double h = 0.5 * double(w) * double(p.dt);
        const double sinc = h == 0.0 ? 1.0 : std::sin(h) / h;
        const double det = std::fabs(double(v)) * std::pow(double(p.dt), 4) * sinc * sinc / 2.0;
        CHECK(q.log_abs_det == Approx(std::log(det)).margin(2e-5));
      }
}

namespace {

// Samples of the model, as (x, y, theta) or, for turning in place, (signed chord, chord direction in (-pi/2, pi/2]
// relative to the start heading, theta), where the density gains the polar factor |chord|.
std::vector<std::array<double, 3>> draw(const Pose2& x0, const VelocityControl& u, const VelocityParams& p, int n,
                                        bool chord_chart) {
  est::Rng rng(20240607u);
  std::vector<std::array<double, 3>> out;
  out.reserve(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) {
    const Pose2 x = VelocityMotionModel::sample(x0, u, p, rng);
    if (!chord_chart) {
      out.push_back({x.x, x.y, x.theta});
      continue;
    }
    const double dx = double(x.x) - double(x0.x), dy = double(x.y) - double(x0.y);
    double psi = std::atan2(dy, dx) - double(x0.theta);
    double c = std::hypot(dx, dy);
    psi = wrap(psi);
    if (psi > kPi / 2) {
      psi -= kPi;
      c = -c;
    } else if (psi <= -kPi / 2) {
      psi += kPi;
      c = -c;
    }
    out.push_back({c, psi, x.theta});
  }
  return out;
}

struct Case {
  const char* name;
  Pose2 x0;
  VelocityControl u;
  VelocityParams p;
  est::test::Grid3 grid;
  bool chord_chart;
};

std::vector<Case> cases() {
  const double th_q = 0.4 + kPi / 2;
  const double mx = 0.3 + (std::sin(th_q) - std::sin(0.4)) * 2.0 / kPi;
  const double my = -0.2 + (std::cos(0.4) - std::cos(th_q)) * 2.0 / kPi;
  return {
      {"quarter circle v = 1, w = pi/2, dt = 1",
       {0.3f, -0.2f, 0.4f},
       {1.0f, est::kHalfPi},
       noisy(1.0f),
       {{mx - 0.75, my - 0.75, th_q - 0.8}, {mx + 0.75, my + 0.75, th_q + 0.8}, {12, 12, 10}},
       false},
      {"straight v = 1, w = 0, dt = 0.5",
       {0.0f, 0.0f, 0.0f},
       {1.0f, 0.0f},
       noisy(0.5f),
       {{0.5 - 0.35, -0.06, -0.25}, {0.5 + 0.35, 0.06, 0.25}, {12, 12, 10}},
       false},
      {"turning in place v = 0, w = 1, dt = 1 (singular at the start point)",
       {0.0f, 0.0f, 0.0f},
       {0.0f, 1.0f},
       noisy(1.0f),
       {{-0.3, 0.5 - 0.3, 1.0 - 0.5}, {0.3, 0.5 + 0.3, 1.0 + 0.5}, {12, 12, 10}},
       true},
  };
}

std::vector<double> cell_masses(const Case& c, int sub) {
  return est::test::integrate_cells(c.grid, sub, [&](double a, double b, double t) {
    if (!c.chord_chart) return static_cast<double>(VelocityMotionModel::likelihood(
        {static_cast<float>(a), static_cast<float>(b), static_cast<float>(t)}, c.u, c.x0, c.p));
    const double ang = double(c.x0.theta) + b;
    const Pose2 x{static_cast<float>(double(c.x0.x) + a * std::cos(ang)),
                  static_cast<float>(double(c.x0.y) + a * std::sin(ang)), static_cast<float>(t)};
    return std::fabs(a) * static_cast<double>(VelocityMotionModel::likelihood(x, c.u, c.x0, c.p));
  });
}

}  // namespace

TEST_CASE("likelihood integrates to one over the pose (with the change of variables table 5.1 omits)",
          "[velocity]") {
  // 36 x 36 x 30 sub-cells x 27 Gauss points = 1.05e6 evaluations per case; the boxes hold >= 6.5 sigma of every
  // direction (no sample of 200k falls outside, checked below). Measured |mass - 1| <= 1e-6 in all three cases
  // (0.99999992, 1.0000003, 1.0000009); table 5.1 without the change of variables would be off by orders of
  // magnitude, and a determinant missing its sinc^2 by 19 % in the quarter circle.
  for (const Case& c : cases()) {
    INFO(c.name);
    const double mass = est::test::total(cell_masses(c, 3));
    INFO("mass " << std::setprecision(9) << mass);
    CHECK(std::fabs(mass - 1.0) < 1e-4);
  }
}

TEST_CASE("sample and likelihood agree: chi-square over 1440 cells at 200k samples, alpha = 0.001", "[velocity]") {
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

TEST_CASE("the book's unnormalized product differs from the density by exactly |det|", "[velocity]") {
  const VelocityParams p = noisy(1.0f);
  const Pose2 x0{0.0f, 0.0f, 0.0f};
  const VelocityControl u{1.0f, est::kHalfPi};
  const Pose2 x{0.62f, 0.66f, 1.55f};
  const est::VelocityPreimage q = est::velocity_preimage(x, u, x0, p);
  const double ratio = static_cast<double>(est::motion_model_velocity_unnormalized(x, u, x0, p)) /
                       static_cast<double>(est::motion_model_velocity(x, u, x0, p));
  CHECK(std::log(ratio) == Approx(q.log_abs_det).margin(1e-4));
  CHECK(std::log(static_cast<double>(VelocityMotionModel::likelihood(x, u, x0, p))) ==
        Approx(VelocityMotionModel::log_likelihood(x, u, x0, p)).margin(1e-5));
}

namespace {

// Jacobians of book_arc by central differences (double), state step 1e-6, control step 1e-5.
void finite_difference(const Pose2& x0, const VelocityControl& u, double dt, double G[3][3], double V[3][2]) {
  const double s[3] = {double(x0.x), double(x0.y), double(x0.theta)};
  const double v = double(u.v), w = double(u.w);
  for (int k = 0; k < 3; ++k) {
    double a[3] = {s[0], s[1], s[2]}, b[3] = {s[0], s[1], s[2]};
    a[k] += 1e-6;
    b[k] -= 1e-6;
    const auto ga = book_arc(a[0], a[1], a[2], v, w, dt), gb = book_arc(b[0], b[1], b[2], v, w, dt);
    for (std::size_t r = 0; r < 3; ++r) G[r][k] = (ga[r] - gb[r]) / 2e-6;
  }
  for (int k = 0; k < 2; ++k) {
    const double e = 1e-5;
    const double va = v + (k == 0 ? e : 0.0), vb = v - (k == 0 ? e : 0.0);
    const double wa = w + (k == 1 ? e : 0.0), wb = w - (k == 1 ? e : 0.0);
    const auto ga = book_arc(s[0], s[1], s[2], va, wa, dt), gb = book_arc(s[0], s[1], s[2], vb, wb, dt);
    for (std::size_t r = 0; r < 3; ++r) V[r][k] = (ga[r] - gb[r]) / (2.0 * e);
  }
}

}  // namespace

TEST_CASE("Jacobians G, V match central differences of eq. 5.9, also at and near w = 0", "[velocity]") {
  // Tolerance 2e-5 (1 + |entry|): float evaluation against double differences whose error is below 1e-8 except at
  // w = 0 and 1e-7, where the control step straddles the straight line and eq. 5.9 loses ~1e-10 / 1e-5.
  const Pose2 x0{0.4f, -1.0f, 0.7f};
  const float ws[] = {1.1f, -0.4f, 3.0f, 1e-3f, 1e-7f, 0.0f};
  for (float dt : {0.2f, 1.0f})
    for (float w : ws) {
      VelocityParams p = noisy(dt);
      const VelocityControl u{1.3f, w};
      const auto j = VelocityMotionModel::jacobians(x0, u, p);
      double G[3][3], V[3][2];
      finite_difference(x0, u, double(dt), G, V);
      INFO("w " << w << " dt " << dt);
      for (int r = 0; r < 3; ++r) {
        for (int k = 0; k < 3; ++k) CHECK(j.G(r, k) == Approx(G[r][k]).margin(2e-5 * (1 + std::fabs(G[r][k]))));
        for (int k = 0; k < 2; ++k) CHECK(j.V(r, k) == Approx(V[r][k]).margin(2e-5 * (1 + std::fabs(V[r][k]))));
      }
      CHECK(j.M(0, 0) == Approx(0.01 * 1.69 + 0.002 * double(w) * double(w)).epsilon(1e-6));
      CHECK(j.M(1, 1) == Approx(0.004 * 1.69 + 0.004 * double(w) * double(w)).epsilon(1e-6));
      CHECK(j.M(0, 1) == 0.0f);
    }
  SECTION("table 7.2's closed form for w != 0") {
    const double v = 1.3, w = 1.1, dt = 0.2, th = 0.7;
    const auto j = VelocityMotionModel::jacobians(x0, {1.3f, 1.1f}, noisy(0.2f));
    const double s = std::sin(th), c = std::cos(th), s2 = std::sin(th + w * dt), c2 = std::cos(th + w * dt);
    CHECK(j.G(0, 2) == Approx(-v / w * c + v / w * c2).margin(1e-6));
    CHECK(j.G(1, 2) == Approx(-v / w * s + v / w * s2).margin(1e-6));
    CHECK(j.V(0, 0) == Approx((-s + s2) / w).margin(1e-6));
    CHECK(j.V(0, 1) == Approx(v * (s - s2) / (w * w) + v * c2 * dt / w).margin(1e-6));
    CHECK(j.V(1, 0) == Approx((c - c2) / w).margin(1e-6));
    CHECK(j.V(1, 1) == Approx(-v * (c - c2) / (w * w) + v * s2 * dt / w).margin(1e-6));
  }
}

TEST_CASE("same seed gives the same bits; different seeds differ", "[velocity]") {
  const VelocityParams p = noisy(0.1f);
  const auto run = [&](std::uint64_t seed) {
    est::Rng rng(seed);
    std::vector<std::uint32_t> out;
    Pose2 x{};
    for (int i = 0; i < 1000; ++i) {
      x = VelocityMotionModel::sample(x, {0.8f, 0.3f}, p, rng);
      out.push_back(bits(x.x));
      out.push_back(bits(x.y));
      out.push_back(bits(x.theta));
      out.push_back(bits(VelocityMotionModel::log_likelihood(x, {0.8f, 0.3f}, Pose2{}, p)));
    }
    return out;
  };
  CHECK(run(7u) == run(7u));
  CHECK(run(7u) != run(8u));
}

TEST_CASE("check rejects non-finite and out-of-range inputs with the right status", "[velocity]") {
  using est::MotionStatus;
  const float nan = std::nanf("");
  const float inf = INFINITY;
  const VelocityParams ok = noisy(0.1f);
  CHECK(VelocityMotionModel::check({1.0f, 0.5f}, ok) == MotionStatus::ok);
  CHECK(VelocityMotionModel::check({nan, 0.5f}, ok) == MotionStatus::rejected_nonfinite);
  CHECK(VelocityMotionModel::check({1.0f, inf}, ok) == MotionStatus::rejected_nonfinite);
  VelocityParams p = ok;
  p.a3 = nan;
  CHECK(VelocityMotionModel::check({1.0f, 0.5f}, p) == MotionStatus::rejected_nonfinite);
  p = ok;
  p.dt = nan;
  CHECK(VelocityMotionModel::check({1.0f, 0.5f}, p) == MotionStatus::rejected_nonfinite);
  for (float dt : {0.0f, -0.1f, 1e-9f, 1000.0f}) {
    p = ok;
    p.dt = dt;
    CHECK(VelocityMotionModel::check({1.0f, 0.5f}, p) == MotionStatus::rejected_range);
  }
  p = ok;
  p.a2 = -1e-6f;
  CHECK(VelocityMotionModel::check({1.0f, 0.5f}, p) == MotionStatus::rejected_range);
  p = ok;
  p.a6 = 2e6f;
  CHECK(VelocityMotionModel::check({1.0f, 0.5f}, p) == MotionStatus::rejected_range);
  CHECK(VelocityMotionModel::check({101.0f, 0.5f}, ok) == MotionStatus::rejected_range);
  CHECK(VelocityMotionModel::check({1.0f, -101.0f}, ok) == MotionStatus::rejected_range);
}

TEST_CASE("likelihood stays finite at its singular points and for far or non-finite states", "[velocity]") {
  const float nan = std::nanf("");
  VelocityParams zero{};
  zero.dt = 0.1f;
  const VelocityParams p = noisy(1e-6f);
  const Pose2 x0{1.0f, 1.0f, 0.0f};
  struct Probe {
    Pose2 x;
    VelocityControl u;
    VelocityParams p;
  };
  const Probe probes[] = {
      {x0, {0.0f, 1.0f}, noisy(1.0f)},                        // rotation in place, end point on the start
      {x0, {0.0f, 0.0f}, zero},                               // stationary, zero noise: point mass
      {VelocityMotionModel::predict(x0, {1.0f, 0.3f}, zero), {1.0f, 0.3f}, zero},  // zero noise, on the mean
      {{1.0f + 1e-3f, 1.0f, 0.0f}, {100.0f, 100.0f}, p},      // extreme control, smallest dt
      {{3e38f, -3e38f, 1.0f}, {1.0f, 0.0f}, noisy(1.0f)},     // far: chord overflows
      {{1.0f, 2.0f, -3.1f}, {-100.0f, -100.0f}, noisy(100.0f)},
      {{nan, 1.0f, 0.0f}, {1.0f, 0.0f}, noisy(1.0f)},
  };
  for (const Probe& pr : probes) {
    REQUIRE(est::usable(VelocityMotionModel::check(pr.u, pr.p)));
    const float l = VelocityMotionModel::likelihood(pr.x, pr.u, x0, pr.p);
    const float ll = VelocityMotionModel::log_likelihood(pr.x, pr.u, x0, pr.p);
    CHECK(std::isfinite(l));
    CHECK(l >= 0.0f);
    CHECK(std::isfinite(ll));
    CHECK(ll >= est::motion_density::kLogZero);
    CHECK(ll <= est::motion_density::kMaxLogDensity);
    const auto j = VelocityMotionModel::jacobians(x0, pr.u, pr.p);
    CHECK(j.G.allFinite());
    CHECK(j.V.allFinite());
    CHECK(j.M.allFinite());
  }
  CHECK(VelocityMotionModel::likelihood({nan, 1.0f, 0.0f}, {1.0f, 0.0f}, x0, noisy(1.0f)) == 0.0f);
}
