#pragma once
// A synthetic office, the simulator's built-in world (and estimator_node's --map office): 20 m x 15 m at 0.05 m (400 x 300
// cells), outer walls, rooms with doors, a corridor, furniture blocks, a round pillar, diagonal wall and an unknown
// patch; asymmetric on purpose (global localization can converge). Origin (0, 0) at the lower-left corner.
#include "est/map/landmark_map.hpp"
#include "est/map/occupancy_grid.hpp"

namespace est::sim {

inline constexpr std::int32_t kOfficeWidth = 400;
inline constexpr std::int32_t kOfficeHeight = 300;
inline constexpr float kOfficeResolution = 0.05f;

// Fills `out` (capacity at least 400 x 300); throws std::runtime_error if it does not fit.
void make_office_map(est::OccupancyGridBuffer& out);

// The office's 16 posts, signatures 1..16, placed without symmetry.
void make_office_landmarks(est::LandmarkMapBuffer& out);

}  // namespace est::sim
