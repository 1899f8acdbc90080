#include <catch2/catch.hpp>
#include <cmath>
#include <vector>

#include "est/map/ray_casting.hpp"
#include "statistics.hpp"
#include "world/landmark_sensor.hpp"
#include "world/office_world.hpp"
#include "world/range_sensor.hpp"
#include "world/robots.hpp"

// The simulated world's sensors against their stated models (sim_host/world): the scenarios' figures are only as
// good as these.
TEST_CASE("synthesized ranges are the exact cast plus N(0, sigma^2), max readings at range_max", "[sim_world]") {
  const auto& w = est::sim::office_world();
  const est::GridRayCaster exact(w.grid());
  const est::ScanLayout layout = est::sim::lidar_360(12.0f);
  const est::sim::RangeNoise noise{0.03f, 0.0f, 0.0f};
  est::Rng rng(2u);
  std::vector<float> ranges;
  std::vector<double> residuals;
  int max_readings = 0, max_expected = 0;
  for (int s = 0; s < 30; ++s) {
    const est::Pose2 pose = w.route.pose_on_segment(static_cast<std::size_t>(s) % 7u, 0.1f * static_cast<float>(s % 9));
    est::sim::simulate_scan(w.grid(), pose, {}, layout, noise, rng, ranges);
    REQUIRE(ranges.size() == 360u);
    for (int k = 0; k < 360; ++k) {
      const float a = pose.theta + layout.angle_min + static_cast<float>(k) * layout.angle_increment;
      const float z_true = exact.cast(pose.x, pose.y, std::cos(a), std::sin(a), 12.0f);
      const float z = ranges[static_cast<std::size_t>(k)];
      if (z_true >= 12.0f) {
        ++max_expected;
        max_readings += z == 12.0f ? 1 : 0;
      } else if (z_true < 11.8f) {
        residuals.push_back((static_cast<double>(z) - static_cast<double>(z_true)) / 0.03);
      }
    }
  }
  CHECK(max_readings == max_expected);
  REQUIRE(residuals.size() > 5000u);
  CHECK(est::test::ks_statistic(residuals, est::test::normal_cdf) < est::test::ks_critical(residuals.size(), 0.001));
}

TEST_CASE("landmark sightings respect range, field of view and walls", "[sim_world]") {
  const auto& w = est::sim::office_world();
  const est::LandmarkMap lm = w.landmarks();
  est::sim::LandmarkSensorSpec spec;
  spec.max_range = 6.0f;
  spec.fov = 3.14159265f;  // 180 deg ahead
  est::Rng rng(4u);
  std::vector<est::sim::Sighting> seen;
  // In the corridor at (7, 7.3) looking east: landmark 3 (8.5, 8.1) is ahead and in view; landmark 2 (4.5, 6.5) is
  // behind; landmark 16 (9.7, 5.0) is ahead but behind the corridor's south wall (door at x 9..10 is not in line).
  const est::Pose2 pose{7.0f, 7.3f, 0.0f};
  est::sim::simulate_landmarks(w.grid(), lm, pose, spec, rng, seen);
  bool saw3 = false, saw2 = false, saw16 = false;
  for (const auto& s : seen) {
    saw3 |= s.c == 2;
    saw2 |= s.c == 1;
    saw16 |= s.c == 15;
    const est::LandmarkMeasurement e = est::expected_landmark_measurement(pose, lm[s.c]);
    CHECK(e.range <= 6.0f);
    CHECK(std::fabs(e.bearing) <= 0.5f * spec.fov);
    CHECK(std::fabs(s.f.range - e.range) < 6.0f * spec.noise.sigma_range);
  }
  CHECK(saw3);
  CHECK_FALSE(saw2);
  CHECK_FALSE(saw16);
  est::sim::simulate_landmarks(est::OccupancyGrid{}, lm, pose, spec, rng, seen);  // no map: no occlusion
  bool saw16_no_walls = false;
  for (const auto& s : seen) saw16_no_walls |= s.c == 15;
  CHECK(saw16_no_walls);
}

TEST_CASE("a kidnapped robot continues its route from where it was put", "[sim_world]") {
  const auto& w = est::sim::office_world();
  est::BicycleParams p;
  p.frame_length = 0.6f;
  p.steer_max = 1.0f;
  est::sim::BicycleRobot bike(w.route, w.route.pose_on_segment(0, 0.0f), 1, p, 0.8f);
  est::Rng rng(1u);
  for (int t = 0; t < 20; ++t) bike.step(rng);
  const est::Pose2 there = w.route.pose_on_segment(3, 0.5f);
  bike.teleport(there, 4);
  bike.step(rng);
  CHECK(std::hypot(bike.pose().x - there.x, bike.pose().y - there.y) < 0.1f);  // one 0.1 s step at <= 0.8 m/s
}

TEST_CASE("the omnidirectional and holonomic robots drive the route with sideways motion", "[sim_world]") {
  // Over a lap's first 40 s: the omni base's body velocity has a leftward part (v2) as large as half its forward
  // part at times, while its heading swings on its own; the holonomic robot never turns and still follows the
  // route (which turns through 90 deg corners), so most of its travel is sideways at some point. Both stay in the
  // free space.
  const auto& w = est::sim::office_world();
  est::sim::RobotTruth truth;
  float rows[4][3] = {};
  est::mecanum_wheel_rows(0.2f, 0.2f, rows);
  REQUIRE(est::configure_omni_wheels(truth.omni_wheels, rows, 4, 0.0005f));
  truth.omni.dt = 0.01f;
  for (const est::sim::RobotKind kind : {est::sim::RobotKind::omni, est::sim::RobotKind::holonomic}) {
    const est::Pose2 start = w.route.pose_on_segment(0, 0.0f);
    const auto robot = est::sim::make_robot(kind, w.route, start, 1, truth, 0.8f, 0.01f, 0.0005);
    est::Rng rng(3u);
    float max_sideways = 0.0f, max_turn = 0.0f, path = 0.0f;
    for (int k = 0; k < 4000; ++k) {
      const est::Pose2 before = robot->pose();
      const est::sim::RobotStep s = robot->step(rng);
      const est::Pose2 after = robot->pose();
      path += std::hypot(after.x - before.x, after.y - before.y);
      max_sideways = std::max(max_sideways, std::fabs(s.v2_mps));
      max_turn = std::max(max_turn, std::fabs(std::remainder(after.theta - start.theta, 6.2831853f)));
      std::int32_t cx = 0, cy = 0;
      REQUIRE(w.grid().world_to_cell(after.x, after.y, cx, cy));
      REQUIRE(w.grid().classify(cx, cy) != est::CellClass::occupied);
      if (kind == est::sim::RobotKind::omni) REQUIRE(s.wheels == 4u);
    }
    INFO("robot " << static_cast<int>(kind));
    CHECK(path > 20.0f);          // it drives the route (0.8 m/s for 40 s, slower at the waypoints)
    CHECK(max_sideways > 0.4f);   // m/s to its left or right
    if (kind == est::sim::RobotKind::holonomic)
      CHECK(max_turn < 0.05f);    // its heading drifts by the truth's noise only
    else
      CHECK(max_turn > 0.5f);     // the omni base turns on its own schedule
  }
}
