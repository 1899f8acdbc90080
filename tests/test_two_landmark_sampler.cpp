#include <catch2/catch.hpp>
#include <cmath>

#include "est/filter/two_landmark_sampler.hpp"

namespace {

est::LandmarkMapStorage<8> g_map;

float wrap(float a) { return std::remainder(a, 6.2831853f); }

}  // namespace

TEST_CASE("two-landmark recovery poses scatter around the true pose by the sensor noise", "[two_landmark_sampler]") {
  g_map.clear();
  REQUIRE(g_map.add({0.0f, 0.0f, 1.0f}) == est::MapStatus::ok);
  REQUIRE(g_map.add({4.0f, 1.0f, 2.0f}) == est::MapStatus::ok);
  REQUIRE(g_map.add({1.0f, 5.0f, 3.0f}) == est::MapStatus::ok);
  const est::LandmarkNoise noise{0.05f, 0.02f, 0.0f};
  est::TwoLandmarkSampler<4> draw(g_map.view(), noise);
  const est::Pose2 truth{2.0f, 2.0f, 0.7f};
  est::Pose2 p;
  est::Rng rng(5u);
  CHECK_FALSE(draw(rng, p));  // nothing seen
  for (std::int32_t j = 0; j < 3; ++j) REQUIRE(draw.add(est::expected_landmark_measurement(truth, g_map.view()[j]), j));
  CHECK_FALSE(draw.add({1.0f, 0.0f, 0.0f}, 7));  // no such landmark
  const int n = 4000;
  double sx = 0.0, sy = 0.0, sxx = 0.0, sth = 0.0;
  for (int i = 0; i < n; ++i) {
    REQUIRE(draw(rng, p));
    const double dx = p.x - truth.x, dy = p.y - truth.y, dth = wrap(p.theta - truth.theta);
    sx += dx;
    sy += dy;
    sxx += dx * dx + dy * dy;
    sth += dth * dth;
  }
  // Unbiased to within 4 standard errors (position sigma ~ 0.06 m: 0.004 m), spread of the order of the noise.
  CHECK(std::fabs(sx / n) < 0.006);
  CHECK(std::fabs(sy / n) < 0.006);
  const double rms_pos = std::sqrt(sxx / n), rms_th = std::sqrt(sth / n);
  INFO("rms position " << rms_pos << " m, heading " << rms_th << " rad");
  CHECK(rms_pos > 0.02);
  CHECK(rms_pos < 0.2);
  CHECK(rms_th < 0.08);
}

TEST_CASE("a wrong pairing (landmark seen where the map says it cannot be) is refused", "[two_landmark_sampler]") {
  g_map.clear();
  REQUIRE(g_map.add({0.0f, 0.0f, 1.0f}) == est::MapStatus::ok);
  REQUIRE(g_map.add({4.0f, 0.0f, 2.0f}) == est::MapStatus::ok);
  est::TwoLandmarkSampler<4> draw(g_map.view(), {0.05f, 0.02f, 0.0f});
  // Both seen 1 m away, 2 m apart, where the map puts them 4 m apart.
  REQUIRE(draw.add({1.0f, 1.5707963f, 1.0f}, 0));
  REQUIRE(draw.add({1.0f, -1.5707963f, 2.0f}, 1));
  est::Rng rng(2u);
  est::Pose2 p;
  CHECK_FALSE(draw(rng, p));
}
