#include "world/landmark_sensor.hpp"

#include <cmath>

#include "est/map/ray_casting.hpp"

namespace est::sim {

void simulate_landmarks(const OccupancyGrid& world, const LandmarkMap& map, const Pose2& robot,
                        const LandmarkSensorSpec& spec, Rng& rng, std::vector<Sighting>& out) {
  out.clear();
  for (std::int32_t j = 0; j < map.size(); ++j) {
    const LandmarkMeasurement e = expected_landmark_measurement(robot, map[j]);
    if (e.range > spec.max_range || std::fabs(e.bearing) > 0.5f * spec.fov) continue;
    if (world.valid() && e.range > 0.0f) {
      const float dx = (map[j].x - robot.x) / e.range, dy = (map[j].y - robot.y) / e.range;
      if (GridRayCaster(world).cast(robot.x, robot.y, dx, dy, e.range) < e.range - 0.05f) continue;  // occluded
    }
    out.push_back({sample_landmark_measurement(robot, map[j], spec.noise, rng), j});
  }
}

}  // namespace est::sim
