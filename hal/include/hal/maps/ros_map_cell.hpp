#pragma once
// ROS map_server's rule from an image pixel to an occupancy cell (wiki.ros.org/map_server), in one place for every
// loader: the host's (hal/maps/ros_map_loader.hpp, YAML + PGM) and the board image's (firmware/target/mps2), so the
// same image gives the same grid on both by construction. Board-buildable: no heap, no exceptions, no libm.
//
// p = (maxval - v) / maxval (v / maxval when negate); trinary: p > occupied_thresh -> occupied (100),
// p < free_thresh -> free (0), else unknown (255); scale: the same ends and round(99 (p - free) / (occ - free))
// between; raw: the pixel value itself (0..100, anything else unknown). Computed in double, as map_server does (on
// a board without a double FPU that is software arithmetic, exact all the same; a loader may tabulate the rule
// once per pixel value). Image rows run top to bottom: image row r is grid row height - 1 - r.
#include <cstdint>

#include "est/map/occupancy_grid.hpp"

namespace hal::maps {

enum class MapMode { trinary, scale, raw };

struct PixelRule {
  MapMode mode = MapMode::trinary;
  bool negate = false;
  double occupied_thresh = 0.65;
  double free_thresh = 0.196;
  std::uint32_t maxval = 255;  // of the image, > 0
};

inline std::uint8_t ros_map_cell(std::uint32_t v, const PixelRule& r) {
  if (r.mode == MapMode::raw) return v <= 100u ? static_cast<std::uint8_t>(v) : est::kUnknownCell;
  const double maxval = r.maxval;
  const double p = r.negate ? v / maxval : (maxval - v) / maxval;
  if (p > r.occupied_thresh) return est::kOccupiedCell;
  if (p < r.free_thresh) return est::kFreeCell;
  if (r.mode != MapMode::scale) return est::kUnknownCell;
  // p in [free, occ]: s in [0, 99], rounded half away from zero (std::lround's rule; s - floor(s) is exact).
  const double s = 99.0 * (p - r.free_thresh) / (r.occupied_thresh - r.free_thresh);
  std::uint32_t n = static_cast<std::uint32_t>(s);
  if (s - n >= 0.5) ++n;
  return static_cast<std::uint8_t>(n);
}

inline std::int32_t ros_map_grid_row(std::int32_t image_row, std::int32_t image_height) {
  return image_height - 1 - image_row;
}

}  // namespace hal::maps
