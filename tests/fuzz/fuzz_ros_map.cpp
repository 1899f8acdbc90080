// libFuzzer target: the ROS map loader's parsers (hal/maps/ros_map_loader.hpp) on any text. The first byte picks a
// PGM image (P5 or P2; converted into a 64 x 64 grid with the trinary rule) or a map_server YAML. Bad input throws
// MapLoadError with the name, nothing else escapes; what is accepted is within its stated bounds.
#include <cstddef>
#include <cstdint>
#include <string>

#include "est/map/occupancy_grid.hpp"
#include "hal/maps/ros_map_loader.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 1) return 0;
  const bool yaml = (data[0] & 1) != 0;
  const std::string text(reinterpret_cast<const char*>(data + 1), size - 1);
  static est::OccupancyGridStorage<64, 64> grid;
  try {
    if (yaml) {
      const hal::maps::RosMapInfo info = hal::maps::parse_ros_map_yaml(text, "fuzz.yaml");
      if (info.image.empty() || !(info.resolution > 0.0f) || !(info.free_thresh < info.occupied_thresh))
        __builtin_trap();
    } else {
      const hal::maps::PgmImage img = hal::maps::parse_pgm(text, "fuzz.pgm");
      if (img.width <= 0 || img.height <= 0 || img.maxval <= 0 ||
          img.pixels.size() != static_cast<std::size_t>(img.width) * static_cast<std::size_t>(img.height))
        __builtin_trap();
      for (std::uint16_t v : img.pixels)
        if (v > img.maxval) __builtin_trap();
      hal::maps::RosMapInfo info;
      info.resolution = 0.05f;
      hal::maps::image_to_grid(img, info, grid, "fuzz.pgm");
      if (grid.width() != img.width || grid.height() != img.height) __builtin_trap();
    }
  } catch (const hal::maps::MapLoadError& e) {
    if (std::string(e.what()).rfind("fuzz.", 0) != 0) __builtin_trap();
  }
  return 0;
}
