// The motion a prediction is handed (est/loop/motion_input.hpp): encoder ticks summed per wheel, odometry increments
// composed, steering sampled and held, the twist averaged over the interval for the time each sample held; an
// increment spanning a correction split there without losing or doubling any of it.
#include <catch2/catch.hpp>

#include "est/loop/motion_input.hpp"

namespace {

using est::loop::MotionGather;
using est::loop::TimeNs;
constexpr TimeNs kMs = 1000000;

est::loop::WheelTicksInput ticks(TimeNs t, std::int32_t a, std::int32_t b, std::int32_t c, std::int32_t d,
                                 std::uint8_t n) {
  est::loop::WheelTicksInput in;
  in.t_ns = t;
  in.ticks[0] = a;
  in.ticks[1] = b;
  in.ticks[2] = c;
  in.ticks[3] = d;
  in.wheel_count = n;
  return in;
}

// A queued increment, as the loop's queue holds it.
est::loop::QueuedInput queued(const est::loop::WheelTicksInput& in) {
  est::loop::QueuedInput q;
  q.kind = est::loop::InputKind::wheel_ticks;
  q.t_ns = in.t_ns;
  q.p.ticks = in;
  return q;
}
est::loop::QueuedInput queued(const est::loop::OdometryInput& in) {
  est::loop::QueuedInput q;
  q.kind = est::loop::InputKind::odometry;
  q.t_ns = in.t_ns;
  q.p.odometry = in;
  return q;
}

}  // namespace

TEST_CASE("before any input the motion is empty: no wheels, identity odometry, no twist, no steering",
          "[motion_input]") {
  MotionGather g;
  g.start(0);
  const est::loop::MotionInput m = g.motion(0, 10 * kMs);
  CHECK(m.dt_s == Approx(0.01f));
  CHECK(m.wheel_count == 0u);
  for (std::int32_t t : m.ticks) CHECK(t == 0);
  CHECK(m.odometry.is_identity());
  CHECK_FALSE(m.twist_known);
  CHECK(m.twist.v1_mps == 0.0f);
  CHECK_FALSE(m.steering_known);
}

TEST_CASE("ticks are summed per wheel over the interval, the wheel count is the latest sample's", "[motion_input]") {
  MotionGather g;
  g.start(0);
  g.add(ticks(4 * kMs, 1, -2, 3, 4, 4));
  g.add(ticks(8 * kMs, 10, 20, -30, 40, 4));
  est::loop::MotionInput m = g.motion(0, 10 * kMs);
  CHECK(m.wheel_count == 4u);
  CHECK(m.ticks[0] == 11);
  CHECK(m.ticks[1] == 18);
  CHECK(m.ticks[2] == -27);
  CHECK(m.ticks[3] == 44);
  g.consumed();
  m = g.motion(10 * kMs, 20 * kMs);
  for (std::int32_t t : m.ticks) CHECK(t == 0);  // each tick once
  CHECK(m.wheel_count == 4u);
}

TEST_CASE("odometry increments compose: (x_bar_0 (-) x_bar_1) (+) (x_bar_1 (-) x_bar_2)", "[motion_input]") {
  const est::Pose2 p0{1.0f, 2.0f, 0.3f}, p1{1.4f, 2.1f, 0.9f}, p2{1.5f, 2.6f, 1.7f};
  MotionGather g;
  g.start(0);
  g.add(est::loop::OdometryInput{5 * kMs, est::between(p0, p1)});
  g.add(est::loop::OdometryInput{10 * kMs, est::between(p1, p2)});
  const est::Pose2 m = g.motion(0, 10 * kMs).odometry;
  const est::Pose2 whole = est::between(p0, p2);
  CHECK(m.x == Approx(whole.x).margin(1e-6));
  CHECK(m.y == Approx(whole.y).margin(1e-6));
  CHECK(m.theta == Approx(whole.theta).margin(1e-6));
  g.consumed();
  CHECK(g.motion(10 * kMs, 20 * kMs).odometry.is_identity());
}

TEST_CASE("steering is the latest sample, held across intervals", "[motion_input]") {
  MotionGather g;
  g.start(0);
  g.add(est::loop::SteeringInput{2 * kMs, 0.1f});
  g.add(est::loop::SteeringInput{7 * kMs, -0.2f});
  est::loop::MotionInput m = g.motion(0, 10 * kMs);
  CHECK(m.steering_known);
  CHECK(m.steering_rad == -0.2f);
  g.consumed();
  m = g.motion(10 * kMs, 20 * kMs);
  CHECK(m.steering_known);
  CHECK(m.steering_rad == -0.2f);
}

TEST_CASE("the twist is the time average of the samples held piecewise over the interval", "[motion_input]") {
  MotionGather g;
  g.start(0);
  g.add(est::loop::TwistInput{0, 1.0f, 0.0f, 0.5f});
  g.add(est::loop::TwistInput{2 * kMs, 2.0f, 1.0f, 0.5f});   // holds 2..8 ms
  g.add(est::loop::TwistInput{8 * kMs, -1.0f, 0.0f, -0.5f}); // holds 8..10 ms and on
  est::loop::MotionInput m = g.motion(0, 10 * kMs);
  REQUIRE(m.twist_known);
  CHECK(m.twist.v1_mps == Approx((2.0 * 1.0 + 6.0 * 2.0 + 2.0 * -1.0) / 10.0).epsilon(1e-5));
  CHECK(m.twist.v2_mps == Approx(6.0 * 1.0 / 10.0).epsilon(1e-5));
  CHECK(m.twist.w_rps == Approx((8.0 * 0.5 - 2.0 * 0.5) / 10.0).epsilon(1e-5));
  g.consumed();
  // The last sample holds through the next interval whole.
  m = g.motion(10 * kMs, 30 * kMs);
  CHECK(m.twist.v1_mps == Approx(-1.0).epsilon(1e-5));
  CHECK(m.dt_s == Approx(0.02f));
}

TEST_CASE("before the first twist the interval counts as standing still", "[motion_input]") {
  MotionGather g;
  g.start(0);
  g.add(est::loop::TwistInput{6 * kMs, 1.0f, 0.0f, 0.0f});
  const est::loop::MotionInput m = g.motion(0, 10 * kMs);
  CHECK(m.twist_known);
  CHECK(m.twist.v1_mps == Approx(0.4).epsilon(1e-5));  // held for the last 4 ms of 10
}

TEST_CASE("an increment spanning a correction's time is split there: share (+) rest = whole", "[motion_input]") {
  SECTION("encoder ticks, truncated toward zero") {
    MotionGather g;
    g.start(0);
    g.add(ticks(10 * kMs, 5, 5, 0, 0, 2));
    est::loop::QueuedInput next = queued(ticks(30 * kMs, 101, -101, 7, 0, 2));
    g.take_ticks_share(&next, 15 * kMs);  // a quarter of (10, 30]
    const est::loop::MotionInput m = g.motion(0, 15 * kMs);
    CHECK(m.ticks[0] == 5 + 25);
    CHECK(m.ticks[1] == 5 - 25);
    CHECK(m.ticks[2] == 1);
    CHECK(next.p.ticks.ticks[0] == 76);
    CHECK(next.p.ticks.ticks[1] == -76);
    CHECK(next.p.ticks.ticks[2] == 6);
    g.consumed();
    // A second correction in the same span takes its share of what is left, from where the first left off.
    g.take_ticks_share(&next, 20 * kMs);  // (15, 20] of (15, 30]: a third of 76
    CHECK(g.motion(15 * kMs, 20 * kMs).ticks[0] == 25);
    CHECK(next.p.ticks.ticks[0] == 51);
  }
  SECTION("odometry, linear in time, the rest in the share's frame") {
    MotionGather g;
    g.start(0);
    g.add(est::loop::OdometryInput{10 * kMs, {0.1f, 0.0f, 0.0f}});
    const est::Pose2 whole{0.4f, 0.2f, 0.8f};
    est::loop::QueuedInput next = queued(est::loop::OdometryInput{20 * kMs, whole});
    g.take_odometry_share(&next, 15 * kMs);
    const est::Pose2 before = g.motion(0, 15 * kMs).odometry;
    const est::Pose2 expect = est::compose({0.1f, 0.0f, 0.0f}, {0.2f, 0.1f, 0.4f});
    CHECK(before.x == Approx(expect.x).margin(1e-6));
    CHECK(before.y == Approx(expect.y).margin(1e-6));
    CHECK(before.theta == Approx(expect.theta).margin(1e-6));
    const est::Pose2 again = est::compose({0.2f, 0.1f, 0.4f}, next.p.odometry.increment);
    CHECK(again.x == Approx(whole.x).margin(1e-6));
    CHECK(again.y == Approx(whole.y).margin(1e-6));
    CHECK(again.theta == Approx(whole.theta).margin(1e-6));
  }
  SECTION("nothing is split without an increment seen before, or one that ends at or before the time") {
    MotionGather g;
    g.start(0);
    est::loop::QueuedInput next = queued(ticks(30 * kMs, 100, 100, 0, 0, 2));
    g.take_ticks_share(&next, 15 * kMs);  // no encoder sample yet: its motion before the first is unknown
    CHECK(next.p.ticks.ticks[0] == 100);
    g.add(ticks(10 * kMs, 1, 1, 0, 0, 2));
    est::loop::QueuedInput ends = queued(ticks(15 * kMs, 100, 100, 0, 0, 2));
    g.take_ticks_share(&ends, 15 * kMs);  // ends at the correction: applied whole before it anyway
    CHECK(ends.p.ticks.ticks[0] == 100);
    g.take_ticks_share(nullptr, 15 * kMs);
    CHECK(g.motion(0, 15 * kMs).ticks[0] == 1);
    est::loop::QueuedInput odom = queued(est::loop::OdometryInput{30 * kMs, {1.0f, 0.0f, 0.0f}});
    g.take_odometry_share(&odom, 15 * kMs);  // no odometry seen yet
    CHECK(odom.p.odometry.increment.x == 1.0f);
  }
}
