// Planar poses and their composition (est/geometry/pose2.hpp): a (+) b is b given in a's frame (Smith and
// Cheeseman's head-to-tail rule), inverse(a) undoes a, between(a, b) is b in a's frame; headings stay in (-pi, pi].
#include <catch2/catch.hpp>

#include <cmath>

#include "est/geometry/pose2.hpp"

using est::Pose2;

namespace {
void check_near(const Pose2& a, const Pose2& b, double tol = 1e-6) {
  CHECK(a.x == Approx(b.x).margin(tol));
  CHECK(a.y == Approx(b.y).margin(tol));
  CHECK(std::remainder(static_cast<double>(a.theta) - static_cast<double>(b.theta), 2.0 * M_PI) ==
        Approx(0.0).margin(tol));
}
}  // namespace

TEST_CASE("a (+) b moves b's offset into a's frame and adds the headings", "[pose2]") {
  const float q = 0.5f * est::kPi;
  check_near(est::compose({1.0f, 2.0f, q}, {0.5f, 0.25f, 0.1f}), {1.0f - 0.25f, 2.0f + 0.5f, q + 0.1f});
  check_near(est::compose({0.0f, 0.0f, 0.0f}, {3.0f, -1.0f, 2.0f}), {3.0f, -1.0f, 2.0f});
  // Headings wrap into (-pi, pi].
  const Pose2 wrapped = est::compose({0.0f, 0.0f, 3.0f}, {0.0f, 0.0f, 1.0f});
  CHECK(wrapped.theta == Approx(4.0 - 2.0 * M_PI).margin(1e-6));
  CHECK(wrapped.theta <= est::kPi);
  CHECK(wrapped.theta > -est::kPi);
}

TEST_CASE("composition is associative, inverse undoes a pose, between is the relative pose", "[pose2]") {
  const Pose2 a{1.0f, -2.0f, 0.7f}, b{0.3f, 0.4f, -1.2f}, c{-2.0f, 0.5f, 2.9f};
  check_near(est::compose(est::compose(a, b), c), est::compose(a, est::compose(b, c)), 2e-6);
  check_near(est::compose(a, est::inverse(a)), {0.0f, 0.0f, 0.0f});
  check_near(est::compose(est::inverse(a), a), {0.0f, 0.0f, 0.0f});
  check_near(est::inverse(est::inverse(a)), a);
  check_near(est::compose(a, est::between(a, c)), c, 2e-6);
  check_near(est::between(a, a), {0.0f, 0.0f, 0.0f});
  // Between two poses of the same frame: in a's frame, c is ahead of a by the rotated offset.
  const Pose2 r = est::between({1.0f, 1.0f, 0.5f * est::kPi}, {1.0f, 3.0f, est::kPi});
  check_near(r, {2.0f, 0.0f, 0.5f * est::kPi});
}

TEST_CASE("identity and finiteness are what they say", "[pose2]") {
  CHECK(Pose2{}.is_identity());
  CHECK_FALSE(Pose2{0.0f, 0.0f, 1e-7f}.is_identity());
  CHECK(Pose2{1.0f, 2.0f, 3.0f}.is_finite());
  CHECK_FALSE(Pose2{std::nanf(""), 0.0f, 0.0f}.is_finite());
  CHECK_FALSE(Pose2{0.0f, INFINITY, 0.0f}.is_finite());
  CHECK(Pose2::from_vector(Eigen::Vector3f(1.0f, 2.0f, 7.0f)).theta == Approx(7.0 - 2.0 * M_PI).margin(1e-6));
}
