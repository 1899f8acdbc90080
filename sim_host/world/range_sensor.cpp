#include "world/range_sensor.hpp"

#include <cmath>

#include "est/map/ray_casting.hpp"
#include "est/random/samplers.hpp"

namespace est::sim {

void simulate_scan(const OccupancyGrid& world, const Pose2& robot, const Pose2& mount, const ScanLayout& layout,
                   const RangeNoise& noise, Rng& rng, std::vector<float>& ranges) {
  const GridRayCaster caster(world);
  const SensorFrame f = sensor_frame(robot, mount);
  ranges.resize(static_cast<std::size_t>(layout.count));
  for (std::int32_t k = 0; k < layout.count; ++k) {
    const float a = layout.angle_min + static_cast<float>(k) * layout.angle_increment;
    const float ux = std::cos(a), uy = std::sin(a);
    const float z_true = caster.cast(f.x, f.y, f.c * ux - f.s * uy, f.s * ux + f.c * uy, layout.range_max);
    const float u = rng.uniform();
    float z = z_true;
    if (u < noise.p_rand) {
      z = rng.uniform(0.0f, layout.range_max);
    } else if (u < noise.p_rand + noise.p_short) {
      z = rng.uniform(0.0f, z_true);
    } else if (z_true < layout.range_max) {
      z = z_true + sample_normal(rng, noise.sigma);
    }
    if (z < layout.range_min) z = layout.range_min;
    if (z >= layout.range_max) z = layout.range_max;
    ranges[static_cast<std::size_t>(k)] = z;
  }
}

}  // namespace est::sim
