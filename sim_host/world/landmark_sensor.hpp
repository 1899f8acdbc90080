#pragma once
// Landmark sightings synthesized from the true pose: every landmark within range, inside the field of view and in
// line of sight (an exact ray cast in the world's grid reaches it) is measured by the model of Thrun table 6.4
// (sample_landmark_measurement) and reported with its correspondence (the map index).
#include <vector>

#include "est/geometry/pose2.hpp"
#include "est/map/landmark_map.hpp"
#include "est/map/occupancy_grid.hpp"
#include "est/random/xoshiro128.hpp"
#include "est/sensor/landmark_model.hpp"

namespace est::sim {

struct LandmarkSensorSpec {
  float max_range = 6.0f;               // m
  float fov = 6.28318530717958647692f;  // rad, full width centred on the heading
  LandmarkNoise noise{0.05f, 0.02f, 0.1f};
};

struct Sighting {
  LandmarkMeasurement f;
  std::int32_t c;
};

// `world` may be invalid (no occlusion then).
void simulate_landmarks(const OccupancyGrid& world, const LandmarkMap& map, const Pose2& robot,
                        const LandmarkSensorSpec& spec, Rng& rng, std::vector<Sighting>& out);

}  // namespace est::sim
