#pragma once
// A synthetic office, the built-in map of the host nodes, tests and benchmarks: 20 m x 15 m at 0.05 m (400 x 300
// cells), outer walls, rooms with doors, a corridor, furniture blocks, a round pillar, diagonal wall and an unknown
// patch; asymmetric on purpose (global localization can converge). Origin (0, 0) at the lower-left corner.
#include "est/map/occupancy_grid.hpp"

namespace hal::maps {

inline constexpr std::int32_t kOfficeWidth = 400;
inline constexpr std::int32_t kOfficeHeight = 300;
inline constexpr float kOfficeResolution = 0.05f;

// Fills `out` (capacity at least 400 x 300); throws std::runtime_error if it does not fit.
void make_office_map(est::OccupancyGridBuffer& out);

}  // namespace hal::maps
