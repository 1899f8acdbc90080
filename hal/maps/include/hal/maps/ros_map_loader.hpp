#pragma once
// Host loaders that fill an est::OccupancyGridBuffer: ROS map_server maps (YAML + PGM) and bare trinary PGM maps.
// Malformed input throws MapLoadError whose what() names the file and the reason.
//
// ROS map_server semantics (wiki.ros.org/map_server): origin is the world pose of the lower-left pixel; the pixel to
// cell rule (image rows top to bottom, trinary / scale / raw) is hal/maps/ros_map_cell.hpp's, shared with the board
// image's loader. Images: PGM P5 (8 or 16 bit) and P2.
// Not supported, and rejected with a reason: origin yaw != 0, images other than PGM, colour images.
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "est/map/occupancy_grid.hpp"
#include "hal/maps/ros_map_cell.hpp"

namespace hal::maps {

class MapLoadError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct PgmImage {
  std::int32_t width = 0;
  std::int32_t height = 0;
  std::int32_t maxval = 0;
  std::vector<std::uint16_t> pixels;  // row-major, top row first
};

struct RosMapInfo {
  std::string image;  // as written in the YAML
  std::string image_path;  // resolved against the YAML's folder
  float resolution = 0.0f;
  float origin_x = 0.0f, origin_y = 0.0f, origin_yaw = 0.0f;
  bool negate = false;
  double occupied_thresh = 0.65;
  double free_thresh = 0.196;
  MapMode mode = MapMode::trinary;
};

// `name` only labels error messages.
PgmImage parse_pgm(const std::string& bytes, const std::string& name);
PgmImage read_pgm(const std::string& path);
RosMapInfo parse_ros_map_yaml(const std::string& text, const std::string& name);

// Converts an image into the grid with map_server's rules; throws when it does not fit the buffer.
void image_to_grid(const PgmImage& img, const RosMapInfo& info, est::OccupancyGridBuffer& out, const std::string& name);

// map_server YAML + its image.
RosMapInfo load_ros_map(const std::string& yaml_path, est::OccupancyGridBuffer& out);

// The gondsm maps of the CARMEN/Radish logs (intel.pgm, aces.pgm): trinary PGM without YAML (0 occupied, 254 free,
// 205 unknown). Their resolution is not stated; 0.05 m (GMapping's default, consistent with the logs' scan extents
// within 15 %) is used unless given, origin (0, 0) at the lower-left corner (the maps are not registered to the logs).
inline constexpr float kGondsmResolution = 0.05f;
void load_trinary_pgm_map(const std::string& pgm_path, est::OccupancyGridBuffer& out, float resolution = kGondsmResolution,
                          float origin_x = 0.0f, float origin_y = 0.0f);

// $EST_SHARED_DIR/datasets or ../shared/datasets; empty when neither exists (tests skip then).
std::string shared_datasets_dir();

}  // namespace hal::maps
