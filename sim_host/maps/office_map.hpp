#pragma once
// Moved to hal/maps (the host map library that estimator_node and the simulator share, so that no hal tool depends
// on sim_host); this header keeps the simulator's and the tests' est::sim names working.
#include "hal/maps/landmark_file.hpp"
#include "hal/maps/office_map.hpp"

namespace est::sim {
using namespace hal::maps;
}  // namespace est::sim
