// Each model's control assembler (est/loop/control_assembler.hpp, est/loop/controls/*.hpp): which inputs it reads,
// when the robot stood still (no motion, no diffusion), when the motion cannot be a control (rejected), and the
// control and the interval-dependent parameters it makes from the loop's gathered motion.
#include <catch2/catch.hpp>

#include <cmath>

#include "est/loop/control_assemblers.hpp"

namespace {

using est::loop::ControlAssembler;
using est::loop::ControlStatus;
using est::loop::InputKind;
using est::loop::InputKinds;
using est::loop::MotionInput;

MotionInput wheels(float dt_s, std::uint8_t count, std::int32_t a, std::int32_t b, std::int32_t c = 0,
                   std::int32_t d = 0) {
  MotionInput m;
  m.dt_s = dt_s;
  m.wheel_count = count;
  m.ticks[0] = a;
  m.ticks[1] = b;
  m.ticks[2] = c;
  m.ticks[3] = d;
  return m;
}

MotionInput twist(float dt_s, float v1, float v2, float w) {
  MotionInput m;
  m.dt_s = dt_s;
  m.twist_known = true;
  m.twist = {v1, v2, w};
  return m;
}

}  // namespace

TEST_CASE("diff drive: the two wheels' ticks are the control; none is standing still; one wheel is no diff drive",
          "[control_assembler][diff_drive]") {
  using A = ControlAssembler<est::DiffDriveMotionModel>;
  const A::Config c{};
  CHECK(A::inputs(c) == InputKinds(InputKind::wheel_ticks));
  est::DiffDriveParams p;
  est::DiffDriveControl u{};
  CHECK(A::make(wheels(0.01f, 2, 0, 0), c, p, u) == ControlStatus::still);
  CHECK(A::make(wheels(0.01f, 2, 0, 0, 5, 5), c, p, u) == ControlStatus::still);  // only wheels 0 and 1 count
  REQUIRE(A::make(wheels(0.01f, 2, 10, -5), c, p, u) == ControlStatus::ok);
  CHECK(u.left_ticks == 10);
  CHECK(u.right_ticks == -5);
  CHECK(A::make(wheels(0.01f, 1, 10, 0), c, p, u) == ControlStatus::rejected);
  CHECK(A::make(wheels(0.01f, 0, 0, 3), c, p, u) == ControlStatus::rejected);
}

TEST_CASE("bicycle: the traction wheel's travel over dt is the speed, the steering reading the angle",
          "[control_assembler][bicycle]") {
  using A = ControlAssembler<est::BicycleMotionModel>;
  A::Config c;
  c.metres_per_tick = 0.002f;
  CHECK(A::inputs(c) == (InputKind::wheel_ticks | InputKind::steering));
  est::BicycleParams p;
  p.dt = 1.0f;
  est::BicycleControl u{};
  MotionInput m = wheels(0.02f, 2, 15, 99);
  m.steering_known = true;
  m.steering_rad = -0.3f;
  REQUIRE(A::make(m, c, p, u) == ControlStatus::ok);
  CHECK(u.v == Approx(15 * 0.002 / 0.02));  // 1.5 m/s
  CHECK(u.steer == -0.3f);
  CHECK(p.dt == 0.02f);  // the interval, not the configured step
  // The traction encoder may be any wheel.
  c.traction_wheel = 1;
  REQUIRE(A::make(m, c, p, u) == ControlStatus::ok);
  CHECK(u.v == Approx(99 * 0.002 / 0.02));
  // Backwards.
  c.traction_wheel = 0;
  REQUIRE(A::make(wheels(0.01f, 1, -5, 0), c, p, u) == ControlStatus::ok);
  CHECK(u.v == Approx(-1.0));
}

TEST_CASE("bicycle: standing still is no traction-wheel ticks; the rear wheel turning alone is no motion",
          "[control_assembler][bicycle]") {
  using A = ControlAssembler<est::BicycleMotionModel>;
  const A::Config c;
  est::BicycleParams p;
  est::BicycleControl u{};
  CHECK(A::make(wheels(0.01f, 2, 0, 40), c, p, u) == ControlStatus::still);
  CHECK(A::make(wheels(0.01f, 2, 0, 0), c, p, u) == ControlStatus::still);
}

TEST_CASE("bicycle: ticks from a wheel the sample does not have, a bad traction wheel or no interval are rejected",
          "[control_assembler][bicycle]") {
  using A = ControlAssembler<est::BicycleMotionModel>;
  A::Config c;
  est::BicycleParams p;
  est::BicycleControl u{};
  c.traction_wheel = 1;
  CHECK(A::make(wheels(0.01f, 1, 0, 7), c, p, u) == ControlStatus::rejected);  // one wheel reported, wheel 1 used
  c.traction_wheel = 0;
  CHECK(A::make(wheels(0.0f, 2, 7, 0), c, p, u) == ControlStatus::rejected);
  CHECK(A::make(wheels(-0.01f, 2, 7, 0), c, p, u) == ControlStatus::rejected);
  c.traction_wheel = 4;
  CHECK(A::make(wheels(0.01f, 4, 7, 7, 7, 7), c, p, u) == ControlStatus::rejected);
}

TEST_CASE("bicycle without its steering: steering unused, taken as 0 and, if configured, known only that well",
          "[control_assembler][bicycle]") {
  using A = ControlAssembler<est::BicycleMotionModel>;
  A::Config c;
  c.steering_fitted = false;
  c.unknown_steer_sigma = 0.3f;
  CHECK(A::inputs(c) == InputKinds(InputKind::wheel_ticks));
  est::BicycleParams p;
  p.steer_sigma = 0.05f;
  est::BicycleControl u{};
  REQUIRE(A::make(wheels(0.01f, 1, 10, 0), c, p, u) == ControlStatus::ok);  // no steering sample: unknown
  CHECK(u.steer == 0.0f);
  CHECK(p.steer_sigma == 0.3f);
  // A fitted sensor before its first sample: the same.
  c.steering_fitted = true;
  p.steer_sigma = 0.05f;
  REQUIRE(A::make(wheels(0.01f, 1, 10, 0), c, p, u) == ControlStatus::ok);
  CHECK(u.steer == 0.0f);
  CHECK(p.steer_sigma == 0.3f);
  // The configured noise is never narrowed by it.
  p.steer_sigma = 0.5f;
  REQUIRE(A::make(wheels(0.01f, 1, 10, 0), c, p, u) == ControlStatus::ok);
  CHECK(p.steer_sigma == 0.5f);
  // With a reading, the configured noise.
  MotionInput m = wheels(0.01f, 1, 10, 0);
  m.steering_known = true;
  m.steering_rad = 0.2f;
  p.steer_sigma = 0.05f;
  REQUIRE(A::make(m, c, p, u) == ControlStatus::ok);
  CHECK(u.steer == 0.2f);
  CHECK(p.steer_sigma == 0.05f);
}

TEST_CASE("velocity: the averaged twist's (v1, w) held for dt; a sideways v2 has no place in it",
          "[control_assembler][velocity]") {
  using A = ControlAssembler<est::VelocityMotionModel>;
  const A::Config c{};
  CHECK(A::inputs(c) == InputKinds(InputKind::twist));
  est::VelocityParams p;
  est::VelocityControl u{};
  MotionInput none;
  none.dt_s = 0.01f;
  CHECK(A::make(none, c, p, u) == ControlStatus::still);                          // no twist yet
  CHECK(A::make(twist(0.01f, 0.0f, 0.7f, 0.0f), c, p, u) == ControlStatus::still);  // only sideways
  REQUIRE(A::make(twist(0.02f, 0.8f, 0.7f, -0.4f), c, p, u) == ControlStatus::ok);
  CHECK(u.v == 0.8f);
  CHECK(u.w == -0.4f);
  CHECK(p.dt == 0.02f);
  REQUIRE(A::make(twist(0.01f, 0.0f, 0.0f, 0.5f), c, p, u) == ControlStatus::ok);  // turning on the spot
  CHECK(A::make(twist(0.0f, 0.8f, 0.0f, 0.0f), c, p, u) == ControlStatus::rejected);
}

TEST_CASE("omni from the twist: (v1, v2, w) held for dt", "[control_assembler][omni]") {
  using A = ControlAssembler<est::OmniMotionModel>;
  const A::Config c{};  // the twist by default
  CHECK(A::inputs(c) == InputKinds(InputKind::twist));
  est::OmniParams p;
  est::OmniControl u{};
  CHECK(A::make(twist(0.01f, 0.0f, 0.0f, 0.0f), c, p, u) == ControlStatus::still);
  MotionInput none;
  none.dt_s = 0.01f;
  CHECK(A::make(none, c, p, u) == ControlStatus::still);
  REQUIRE(A::make(twist(0.05f, 0.3f, -0.2f, 0.1f), c, p, u) == ControlStatus::ok);
  CHECK(u.v1 == 0.3f);
  CHECK(u.v2 == -0.2f);
  CHECK(u.w == 0.1f);
  CHECK(p.dt == 0.05f);
  REQUIRE(A::make(twist(0.05f, 0.0f, 0.4f, 0.0f), c, p, u) == ControlStatus::ok);  // pure crab
  CHECK(A::make(twist(0.0f, 0.3f, 0.0f, 0.0f), c, p, u) == ControlStatus::rejected);
}

TEST_CASE("omni from mecanum and kiwi wheel ticks: a known body motion gives its (v1, v2, w)",
          "[control_assembler][omni]") {
  using A = ControlAssembler<est::OmniMotionModel>;
  const float mpt = 0.0001f;
  struct Base {
    const char* name;
    int count;
    float rows[4][3];
  };
  Base bases[2] = {{"mecanum X, 0.2 m + 0.15 m", 4, {}}, {"kiwi, three wheels on 0.25 m", 3, {}}};
  est::mecanum_wheel_rows(0.2f, 0.15f, bases[0].rows);
  const float beta[3] = {0.0f, 2.0943951f, 4.1887902f};
  est::omni_wheel_rows(beta, 3, 0.25f, bases[1].rows);
  for (const Base& b : bases) {
    INFO(b.name);
    A::Config c;
    c.source = A::Source::wheels;
    REQUIRE(est::configure_omni_wheels(c.wheels, b.rows, b.count, mpt));
    CHECK(A::inputs(c) == InputKinds(InputKind::wheel_ticks));
    // The body moves at (0.6, -0.25, 0.8) for 50 ms: each wheel's travel is its row times the displacement.
    const float dt = 0.05f, v1 = 0.6f, v2 = -0.25f, w = 0.8f;
    std::int32_t t[4] = {};
    for (int i = 0; i < b.count; ++i)
      t[i] = static_cast<std::int32_t>(std::lround(
          (b.rows[i][0] * v1 * dt + b.rows[i][1] * v2 * dt + b.rows[i][2] * w * dt) / mpt));
    est::OmniParams p;
    est::OmniControl u{};
    REQUIRE(A::make(wheels(dt, static_cast<std::uint8_t>(b.count), t[0], t[1], t[2], t[3]), c, p, u) ==
            ControlStatus::ok);
    // Within the ticks' quantization: half a tick per wheel over dt.
    const double tick_speed = static_cast<double>(mpt / dt);
    CHECK(u.v1 == Approx(v1).margin(2.0 * tick_speed));
    CHECK(u.v2 == Approx(v2).margin(2.0 * tick_speed));
    CHECK(u.w == Approx(w).margin(8.0 * tick_speed));
    CHECK(p.dt == dt);
    CHECK(A::make(wheels(dt, static_cast<std::uint8_t>(b.count), 0, 0, 0, 0), c, p, u) == ControlStatus::still);
    // A sample from another base (another wheel count), or no interval: no control.
    CHECK(A::make(wheels(dt, 2, t[0], t[1]), c, p, u) == ControlStatus::rejected);
    CHECK(A::make(wheels(0.0f, static_cast<std::uint8_t>(b.count), t[0], t[1], t[2], t[3]), c, p, u) ==
          ControlStatus::rejected);
  }
  // Wheels that were never configured cannot make a control.
  A::Config unconfigured;
  unconfigured.source = A::Source::wheels;
  est::OmniParams p;
  est::OmniControl u{};
  CHECK(A::make(wheels(0.01f, 4, 1, 2, 3, 4), unconfigured, p, u) == ControlStatus::rejected);
}

TEST_CASE("holonomic: (u_x, u_y) = (v1, v2) with B = dt I, Q = dt q and the heading drift growing with sqrt(dt)",
          "[control_assembler][holonomic]") {
  using A = ControlAssembler<est::HolonomicPoseMotionModel>;
  A::Config c;
  c.noise_per_s << 0.04f, 0.01f, 0.01f, 0.09f;
  c.heading_sigma_per_sqrt_s = 0.02f;
  CHECK(A::inputs(c) == InputKinds(InputKind::twist));
  est::HolonomicPoseParams p;
  Eigen::Vector2f u = Eigen::Vector2f::Zero();
  MotionInput none;
  none.dt_s = 0.01f;
  CHECK(A::make(none, c, p, u) == ControlStatus::still);
  CHECK(A::make(twist(0.01f, 0.0f, 0.0f, 0.5f), c, p, u) == ControlStatus::still);  // it never steers: no motion
  REQUIRE(A::make(twist(0.25f, 0.4f, -0.3f, 0.5f), c, p, u) == ControlStatus::ok);
  CHECK(u(0) == 0.4f);
  CHECK(u(1) == -0.3f);
  CHECK(p.point.B.isApprox(Eigen::Matrix2f::Identity() * 0.25f));
  CHECK(p.point.B(0, 1) == 0.0f);
  CHECK(p.point.Q(0, 0) == Approx(0.01f));
  CHECK(p.point.Q(0, 1) == Approx(0.0025f));
  CHECK(p.point.Q(1, 1) == Approx(0.0225f));
  CHECK(p.heading_sigma == Approx(0.02f * 0.5f));
  // So the predicted displacement over dt is the twist times dt, in the robot's frame.
  const est::Pose2 x = est::HolonomicPoseMotionModel::predict({1.0f, 2.0f, 0.5f * est::kPi}, u, p);
  CHECK(x.x == Approx(1.0 + 0.075).margin(1e-6));  // facing +y, moving right (v2 < 0) is along world +x
  CHECK(x.y == Approx(2.0 + 0.1).margin(1e-6));
  CHECK(x.theta == Approx(0.5f * est::kPi));
  CHECK(A::make(twist(0.0f, 0.4f, 0.0f, 0.0f), c, p, u) == ControlStatus::rejected);
}

TEST_CASE("odometry: the composed increment is the control (x_bar_{t-1}, x_bar_t) = (identity, increment)",
          "[control_assembler][odometry]") {
  using A = ControlAssembler<est::OdometryMotionModel>;
  const A::Config c{};
  CHECK(A::inputs(c) == InputKinds(InputKind::odometry));
  est::OdometryParams p;
  est::OdometryControl u{};
  MotionInput m;
  m.dt_s = 0.01f;
  CHECK(A::make(m, c, p, u) == ControlStatus::still);  // identity: no odometry motion
  m.odometry = {0.3f, 0.1f, 0.2f};
  REQUIRE(A::make(m, c, p, u) == ControlStatus::ok);
  CHECK(u.odom_prev.is_identity());
  CHECK(u.odom.x == 0.3f);
  CHECK(u.odom.y == 0.1f);
  CHECK(u.odom.theta == 0.2f);
  // Thrun table 5.6 reads only the relative motion: from any pose, the prediction applies the increment there.
  const est::Pose2 x0{4.0f, -1.0f, 2.0f};
  const est::Pose2 x = est::OdometryMotionModel::predict(x0, u, p);
  const est::Pose2 want = est::compose(x0, m.odometry);
  CHECK(x.x == Approx(want.x).margin(1e-5));
  CHECK(x.y == Approx(want.y).margin(1e-5));
  CHECK(x.theta == Approx(want.theta).margin(1e-5));
  // A pure rotation is motion too.
  m.odometry = {0.0f, 0.0f, -0.4f};
  CHECK(A::make(m, c, p, u) == ControlStatus::ok);
}
