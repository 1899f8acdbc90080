// The office as map_server files (office_map_files.hpp).
#include "office_map_files.hpp"

#include <cstdint>
#include <fstream>
#include <memory>
#include <stdexcept>
#include <string>

#include "est/map/occupancy_grid.hpp"
#include "world/office_map.hpp"

namespace est::test {

MapFiles write_office_map_files(const std::string& dir, const std::string& name) {
  auto storage = std::make_unique<est::OccupancyGridStorage<est::sim::kOfficeWidth, est::sim::kOfficeHeight>>();
  est::sim::make_office_map(*storage);
  const est::OccupancyGrid g = storage->grid();
  MapFiles f{dir + "/" + name + ".yaml", dir + "/" + name + ".pgm"};

  std::string raster;
  raster.reserve(static_cast<std::size_t>(g.width()) * static_cast<std::size_t>(g.height()));
  for (std::int32_t r = 0; r < g.height(); ++r) {
    const std::int32_t cy = g.height() - 1 - r;  // the image's top row is the grid's last
    for (std::int32_t cx = 0; cx < g.width(); ++cx) {
      const std::uint8_t v = g.at(cx, cy);
      if (v == est::kOccupiedCell) raster += '\x00';
      else if (v == est::kFreeCell) raster += '\xfe';
      else if (v == est::kUnknownCell) raster += '\xcd';
      else throw std::runtime_error("office map: cell value " + std::to_string(v) + " is not trinary");
    }
  }
  std::ofstream pgm(f.pgm, std::ios::binary);
  pgm << "P5\n# the simulator's office (sim_host/world/office_map.hpp)\n"
      << g.width() << " " << g.height() << "\n255\n" << raster;
  if (g.resolution() != 0.05f || g.origin_x() != 0.0f || g.origin_y() != 0.0f)
    throw std::runtime_error("office map: the YAML below states 0.05 m at (0, 0)");
  std::ofstream yaml(f.yaml);
  yaml << "image: " << name << ".pgm\n"
       << "resolution: 0.05\n"
       << "origin: [0.0, 0.0, 0.0]\n"
       << "negate: 0\n"
       << "occupied_thresh: 0.65\n"
       << "free_thresh: 0.196\n"
       << "mode: trinary\n";
  if (!pgm.good() || !yaml.good()) throw std::runtime_error("cannot write " + f.pgm + " or " + f.yaml);
  return f;
}

}  // namespace est::test
