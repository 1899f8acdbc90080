#pragma once
// The simulator's office (sim_host/world/office_map.hpp) as a ROS map_server map, written the way map_saver writes
// one: a trinary P5 PGM (occupied 0, free 254, unknown 205; top row first) and its YAML (resolution, origin, negate 0,
// thresholds 0.65 / 0.196, which classify those three values back to occupied, free and unknown). estimator_node
// (--map FILE.yaml) and the board image read the same two files. Host only.
#include <string>

namespace est::test {

struct MapFiles {
  std::string yaml;  // dir/name.yaml
  std::string pgm;   // dir/name.pgm
};

// Throws std::runtime_error when a file cannot be written or the office has a cell value map_saver cannot express.
MapFiles write_office_map_files(const std::string& dir, const std::string& name);

}  // namespace est::test
