#pragma once
// ROS map_server maps (YAML + PGM) read on the board over semihosting into an est::OccupancyGridBuffer, by the host
// loader's rules (hal/maps/ros_map_loader.hpp) with its pixel rule itself (hal/maps/ros_map_cell.hpp), so the same
// files give the same grid on both. YAML keys: image (relative to the YAML's folder, or absolute), resolution,
// origin [x, y, yaw] (yaw 0), negate, occupied_thresh, free_thresh, mode; others are ignored, as map_server does,
// and a duplicate key is an error, as on the host. Numbers are decimal (decimal.hpp: strtod's value exactly, or
// refused). Images: PGM P5, 8 or 16 bit (the host also reads P2). Every failure is a reason, never a trap.
#include <cstdint>

#include "est/map/occupancy_grid.hpp"
#include "est/util/digest.hpp"

namespace board {

enum class MapError : std::uint8_t {
  none = 0,
  cannot_open_yaml,
  yaml_syntax,        // a line that is not 'key: value'
  duplicate_key,
  missing_key,        // image, resolution, origin, occupied_thresh or free_thresh
  bad_value,          // not a number the board reads, out of range, or an unknown mode
  unsupported,        // origin yaw != 0, more keys than the board tracks, a P2 image
  image_not_pgm,
  path_too_long,
  cannot_open_image,
  bad_pgm_header,
  too_large,          // more cells than the grid buffer holds
  truncated_raster,
  pixel_above_maxval,
};
const char* to_string(MapError e);

struct MapLoadResult {
  MapError error = MapError::none;
  std::uint32_t yaml_line = 0;  // of a YAML error
  float resolution = 0.0f;
  float origin_x = 0.0f, origin_y = 0.0f;
  std::int32_t width = 0, height = 0;
};

MapLoadResult load_ros_map(const char* yaml_path, est::OccupancyGridBuffer& out);

// A digest of a grid's geometry and every cell (the image prints it; the host test compares it with the grid its own
// loader makes of the same files).
inline std::uint64_t grid_digest(const est::OccupancyGrid& g) {
  est::Digest d;
  d.add_u32(static_cast<std::uint32_t>(g.width()));
  d.add_u32(static_cast<std::uint32_t>(g.height()));
  d.add(g.resolution());
  d.add(g.origin_x());
  d.add(g.origin_y());
  for (std::int32_t cy = 0; cy < g.height(); ++cy)
    for (std::int32_t cx = 0; cx < g.width(); ++cx) d.add_u32(g.at(cx, cy));
  return d.value();
}

}  // namespace board
