// Wheel kinematics of an omnidirectional base (est/motion/omni_wheels.hpp): the rows of kiwi and mecanum bases as
// the wheels' geometry gives them, the least-squares inverse exact for travels a rigid motion produced, and no
// configuration from rows that cannot tell every body motion apart.
#include <catch2/catch.hpp>

#include <array>
#include <cmath>
#include <vector>

#include "est/motion/omni_wheels.hpp"

namespace {

// J d: each wheel's travel for the body displacement d = (dx, dy, dtheta).
void travel(const float (*rows)[3], int n, const float d[3], float* s) {
  for (int i = 0; i < n; ++i) s[i] = rows[i][0] * d[0] + rows[i][1] * d[1] + rows[i][2] * d[2];
}

// omni_body_displacement of tick increments (from a buffer the compiler cannot size: GCC's -Warray-bounds would
// otherwise flag the loop over w.count for iterations it cannot rule out).
Eigen::Vector3f body(const est::OmniWheels& w, const std::int32_t* ticks) {
  const std::vector<std::int32_t> t(ticks, ticks + est::kMaxOmniWheels);
  return est::omni_body_displacement(w, t.data());
}

}  // namespace

TEST_CASE("kiwi rows: a wheel on the circle rolls along its tangent, and turning moves every wheel by r dtheta",
          "[omni_wheels]") {
  const float beta[3] = {0.0f, 2.0943951f, 4.1887902f};  // 0, 120, 240 deg
  float rows[3][3];
  est::omni_wheel_rows(beta, 3, 0.2f, rows);
  // The wheel at 0 deg sits on +x and rolls along +y: forward motion does not turn it, leftward motion does.
  CHECK(rows[0][0] == Approx(0.0).margin(1e-7));
  CHECK(rows[0][1] == Approx(1.0));
  CHECK(rows[0][2] == Approx(0.2));
  // The one at 120 deg rolls along (-sin 120, cos 120).
  CHECK(rows[1][0] == Approx(-std::sin(2.0943951)).margin(1e-6));
  CHECK(rows[1][1] == Approx(std::cos(2.0943951)).margin(1e-6));
  for (int i = 0; i < 3; ++i) CHECK(rows[i][2] == Approx(0.2));
  // Against the contact point's velocity: v + w x r(cos b, sin b), along the tangent (-sin b, cos b).
  const float d[3] = {0.03f, -0.02f, 0.1f};
  float s[3];
  travel(rows, 3, d, s);
  for (int i = 0; i < 3; ++i) {
    const double b = static_cast<double>(beta[i]);
    const double px = 0.2 * std::cos(b), py = 0.2 * std::sin(b);
    const double vx = 0.03 - 0.1 * py, vy = -0.02 + 0.1 * px;
    CHECK(s[i] == Approx(-std::sin(b) * vx + std::cos(b) * vy).margin(1e-7));
  }
}

TEST_CASE("mecanum rows, X arrangement: forward drives all four, sideways and turning in opposite pairs",
          "[omni_wheels]") {
  float rows[4][3];
  est::mecanum_wheel_rows(0.2f, 0.15f, rows);
  const float k = 0.35f;
  // front-left, front-right, rear-left, rear-right
  const float want[4][3] = {{1.0f, -1.0f, -k}, {1.0f, 1.0f, k}, {1.0f, 1.0f, -k}, {1.0f, -1.0f, k}};
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 3; ++j) CHECK(rows[i][j] == Approx(want[i][j]));
  const float left[3] = {0.0f, 0.1f, 0.0f};
  float s[4];
  travel(rows, 4, left, s);
  CHECK(s[0] == Approx(-0.1));  // moving left: front-left and rear-right run backwards
  CHECK(s[1] == Approx(0.1));
  CHECK(s[2] == Approx(0.1));
  CHECK(s[3] == Approx(-0.1));
  const float spin[3] = {0.0f, 0.0f, 0.2f};
  travel(rows, 4, spin, s);
  CHECK(s[0] == Approx(-0.07));  // counter-clockwise: the left wheels back, the right wheels forward
  CHECK(s[1] == Approx(0.07));
  CHECK(s[2] == Approx(-0.07));
  CHECK(s[3] == Approx(0.07));
}

TEST_CASE("the least-squares inverse gives back the body motion of consistent travels exactly", "[omni_wheels]") {
  const float mpt = 0.001f;
  float kiwi3[3][3], kiwi4[4][3], mecanum[4][3];
  const float b3[3] = {0.3f, 2.4f, 4.5f};  // any three distinct angles
  const float b4[4] = {0.0f, 1.5707963f, 3.1415927f, 4.712389f};
  est::omni_wheel_rows(b3, 3, 0.25f, kiwi3);
  est::omni_wheel_rows(b4, 4, 0.25f, kiwi4);
  est::mecanum_wheel_rows(0.2f, 0.2f, mecanum);
  struct Base {
    const char* name;
    const float (*rows)[3];
    int n;
  };
  for (const Base& b : {Base{"kiwi3", kiwi3, 3}, Base{"kiwi4", kiwi4, 4}, Base{"mecanum", mecanum, 4}}) {
    INFO(b.name);
    est::OmniWheels w;
    REQUIRE(est::configure_omni_wheels(w, b.rows, b.n, mpt));
    CHECK(w.count == b.n);
    CHECK(w.metres_per_tick == mpt);
    for (const auto& d : {std::array<float, 3>{0.05f, 0.0f, 0.0f}, std::array<float, 3>{0.0f, -0.04f, 0.0f},
                          std::array<float, 3>{0.0f, 0.0f, 0.3f}, std::array<float, 3>{0.03f, 0.02f, -0.2f}}) {
      // Travels in whole ticks (the displacement chosen so that they are), back to the displacement.
      float s[4] = {};
      travel(b.rows, b.n, d.data(), s);
      std::int32_t ticks[4] = {};
      for (int i = 0; i < b.n; ++i) ticks[i] = static_cast<std::int32_t>(std::lround(s[i] / mpt));
      float s_q[4] = {};
      for (int i = 0; i < b.n; ++i) s_q[i] = static_cast<float>(ticks[i]) * mpt;
      const Eigen::Vector3f back = body(w, ticks);
      // Exact for the quantized travels: J (back) reproduces them (the residual of a rigid motion is zero).
      for (int i = 0; i < b.n; ++i)
        CHECK(b.rows[i][0] * back(0) + b.rows[i][1] * back(1) + b.rows[i][2] * back(2) ==
              Approx(s_q[i]).margin(2e-6));
      // And within the quantization of the true displacement.
      CHECK(back(0) == Approx(d[0]).margin(mpt));
      CHECK(back(1) == Approx(d[1]).margin(mpt));
      CHECK(back(2) == Approx(d[2]).margin(4.0f * mpt));
    }
  }
}

TEST_CASE("four wheels that disagree give the least-squares body motion", "[omni_wheels]") {
  float rows[4][3];
  est::mecanum_wheel_rows(0.2f, 0.2f, rows);
  est::OmniWheels w;
  REQUIRE(est::configure_omni_wheels(w, rows, 4, 0.001f));
  // Forward 0.1 m, with wheel 0 slipping 4 ticks short: the inverse spreads the disagreement (a quarter of it forward).
  const std::int32_t ticks[4] = {96, 100, 100, 100};
  const Eigen::Vector3f d = body(w, ticks);
  CHECK(d(0) == Approx(0.099).margin(1e-6));
  CHECK(d(1) == Approx(0.001).margin(1e-6));
  CHECK(d(2) == Approx(0.001 / 0.4).margin(1e-5));
}

TEST_CASE("rows that cannot tell every body motion apart, or a bad configuration, are refused", "[omni_wheels]") {
  est::OmniWheels w;
  // Three wheels all rolling along +y: forward motion is invisible to them.
  const float parallel[3][3] = {{0.0f, 1.0f, 0.2f}, {0.0f, 1.0f, -0.2f}, {0.0f, 1.0f, 0.1f}};
  CHECK_FALSE(est::configure_omni_wheels(w, parallel, 3, 0.001f));
  CHECK(w.count == 0u);
  // A base whose wheels do not see rotation apart from translation (two identical wheels and a third).
  const float twins[3][3] = {{1.0f, 0.0f, 0.2f}, {1.0f, 0.0f, 0.2f}, {0.0f, 1.0f, 0.0f}};
  CHECK_FALSE(est::configure_omni_wheels(w, twins, 3, 0.001f));
  // Wrong counts, a bad resolution, a non-finite row.
  float rows[4][3];
  est::mecanum_wheel_rows(0.2f, 0.2f, rows);
  CHECK_FALSE(est::configure_omni_wheels(w, rows, 2, 0.001f));
  CHECK_FALSE(est::configure_omni_wheels(w, rows, 5, 0.001f));
  CHECK_FALSE(est::configure_omni_wheels(w, rows, 4, 0.0f));
  CHECK_FALSE(est::configure_omni_wheels(w, rows, 4, -0.001f));
  CHECK_FALSE(est::configure_omni_wheels(w, rows, 4, std::nanf("")));
  rows[2][1] = std::nanf("");
  CHECK_FALSE(est::configure_omni_wheels(w, rows, 4, 0.001f));
  CHECK(w.count == 0u);
  // A refused configuration leaves nothing behind: no displacement from any ticks.
  const std::int32_t ticks[4] = {10, 20, 30, 40};
  CHECK(body(w, ticks).isZero());
}
