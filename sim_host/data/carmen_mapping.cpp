// The occupancy grid of a CARMEN log from its corrected poses (data/carmen.hpp: build_carmen_map), Thrun table 9.1
// by est/map/occupancy_grid_mapping.hpp, written as a map_server PGM + YAML.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <vector>

#include "data/carmen.hpp"
#include "est/map/occupancy_grid_mapping.hpp"
#include "node/node_config.hpp"

namespace sim::data {
namespace {

namespace fs = std::filesystem;

est::ScanLayout layout_of(const CarmenScan& s) {
  return {s.geometry.angle_min_rad, s.geometry.angle_increment_rad, static_cast<std::int32_t>(s.ranges.size()),
          s.geometry.range_min_m, s.geometry.range_max_m};
}

est::Pose2 pose_of(const TimedPose& p) {
  return {static_cast<float>(p.x), static_cast<float>(p.y), static_cast<float>(p.theta)};
}

// The sensor's pose in the world, in double.
struct Frame {
  double x, y, c, s;
};
Frame frame_of(const TimedPose& p, const est::Pose2& mount) {
  const est::SensorFrame f = est::sensor_frame(pose_of(p), mount);
  return {static_cast<double>(f.x), static_cast<double>(f.y), static_cast<double>(f.c), static_cast<double>(f.s)};
}

// map_server's trinary image values.
constexpr unsigned char kPgmOccupied = 0, kPgmFree = 254, kPgmUnknown = 205;

}  // namespace

CarmenMap build_carmen_map(const std::vector<CarmenScan>& scans, const est::Pose2& mount, const std::string& stem,
                           const CarmenMapOptions& o) {
  if (scans.empty()) throw std::invalid_argument("build_carmen_map: no scans");
  const double start = wall_seconds();
  // The extent: every pose and every mapped end point, and a margin.
  double x0 = 1e300, y0 = 1e300, x1 = -1e300, y1 = -1e300;
  const auto extend = [&](double x, double y) {
    x0 = std::min(x0, x), y0 = std::min(y0, y), x1 = std::max(x1, x), y1 = std::max(y1, y);
  };
  for (const CarmenScan& s : scans) {
    const Frame f = frame_of(s.reference, mount);
    extend(f.x, f.y);
    for (std::size_t k = 0; k < s.ranges.size(); ++k) {
      const double z = std::min({static_cast<double>(s.ranges[k]), o.max_range_m,
                                 static_cast<double>(s.geometry.range_max_m)});
      if (!(z >= static_cast<double>(s.geometry.range_min_m))) continue;
      const double a = static_cast<double>(s.geometry.angle_min_rad) +
                       static_cast<double>(k) * static_cast<double>(s.geometry.angle_increment_rad);
      const double c = std::cos(a), sn = std::sin(a);
      extend(f.x + z * (f.c * c - f.s * sn), f.y + z * (f.s * c + f.c * sn));
    }
  }
  const double res = o.resolution_m;
  x0 -= res, y0 -= res, x1 += res, y1 += res;
  const int full_w = static_cast<int>(std::ceil((x1 - x0) / res));
  const int full_h = static_cast<int>(std::ceil((y1 - y0) / res));
  if (static_cast<double>(full_w) * full_h > 1.0e8)
    throw std::runtime_error("the scans span " + std::to_string(full_w) + " x " + std::to_string(full_h) +
                             " cells: use a coarser --resolution or a shorter --map-range");
  std::vector<float> full(static_cast<std::size_t>(full_w) * static_cast<std::size_t>(full_h), 0.0f);
  est::LogOddsGrid grid_full(full.data(), full_w, full_h, static_cast<float>(res), static_cast<float>(x0),
                             static_cast<float>(y0));
  est::InverseRangeSensorParams p;
  p.hit_range_max = static_cast<float>(o.max_range_m);
  p.free_range_max = static_cast<float>(o.max_range_m);
  est::MappingCounters counters;
  for (const CarmenScan& s : scans)
    grid_full.update(pose_of(s.reference), mount, layout_of(s), s.ranges.data(), p, counters);

  // The map: the occupied cells' bounding box (free space seen through doors and windows beyond the walls is left
  // out) and the poses, with the margin.
  int c0 = full_w, r0 = full_h, c1 = -1, r1 = -1;
  for (int cy = 0; cy < full_h; ++cy)
    for (int cx = 0; cx < full_w; ++cx)
      if (est::LogOddsGrid::to_cell(grid_full.at(cx, cy)) >= 65 &&
          est::LogOddsGrid::to_cell(grid_full.at(cx, cy)) <= 100)
        c0 = std::min(c0, cx), r0 = std::min(r0, cy), c1 = std::max(c1, cx), r1 = std::max(r1, cy);
  for (const CarmenScan& s : scans) {
    const int cx = static_cast<int>((s.reference.x - x0) / res), cy = static_cast<int>((s.reference.y - y0) / res);
    c0 = std::min(c0, cx), r0 = std::min(r0, cy), c1 = std::max(c1, cx), r1 = std::max(r1, cy);
  }
  const int margin = static_cast<int>(std::ceil(o.margin_m / res));
  c0 = std::max(0, c0 - margin), r0 = std::max(0, r0 - margin);
  c1 = std::min(full_w - 1, c1 + margin), r1 = std::min(full_h - 1, r1 + margin);
  CarmenMap m;
  m.width = c1 - c0 + 1;
  m.height = r1 - r0 + 1;
  if (m.width > node::kMapMaxSide || m.height > node::kMapMaxSide)
    throw std::runtime_error("the map would be " + std::to_string(m.width) + " x " + std::to_string(m.height) +
                             " cells, more than estimator_node's " + std::to_string(node::kMapMaxSide) +
                             " per side: use a coarser --resolution");
  m.resolution_m = res;
  m.origin_x = x0 + c0 * res;
  m.origin_y = y0 + r0 * res;
  x0 = m.origin_x, y0 = m.origin_y;
  std::vector<float> log_odds(static_cast<std::size_t>(m.width) * static_cast<std::size_t>(m.height), 0.0f);
  for (int cy = 0; cy < m.height; ++cy)
    for (int cx = 0; cx < m.width; ++cx)
      log_odds[static_cast<std::size_t>(cy) * static_cast<std::size_t>(m.width) + static_cast<std::size_t>(cx)] =
          grid_full.at(cx + c0, cy + r0);
  const est::LogOddsGrid grid(log_odds.data(), m.width, m.height, static_cast<float>(res), static_cast<float>(x0),
                              static_cast<float>(y0));

  // The image: rows top (largest y) first.
  std::vector<unsigned char> cls(log_odds.size());
  for (int cy = 0; cy < m.height; ++cy)
    for (int cx = 0; cx < m.width; ++cx) {
      const std::uint8_t v = est::LogOddsGrid::to_cell(grid.at(cx, cy));
      const std::size_t i = static_cast<std::size_t>(cy * m.width + cx);
      if (v == est::kUnknownCell || (v > 19 && v < 65)) {
        cls[i] = kPgmUnknown;
        ++m.unknown;
      } else if (v >= 65) {
        cls[i] = kPgmOccupied;
        ++m.occupied;
      } else {
        cls[i] = kPgmFree;
        ++m.free;
      }
    }
  m.pgm = stem + ".pgm";
  m.yaml = stem + ".yaml";
  {
    std::ofstream img(m.pgm, std::ios::binary);
    img << "P5\n" << m.width << " " << m.height << "\n255\n";
    for (int r = 0; r < m.height; ++r)
      img.write(reinterpret_cast<const char*>(&cls[static_cast<std::size_t>(m.height - 1 - r) *
                                                   static_cast<std::size_t>(m.width)]),
                m.width);
    std::ofstream y(m.yaml);
    char buf[256];
    std::snprintf(buf, sizeof buf, "image: %s\nresolution: %.4f\norigin: [%.4f, %.4f, 0.0]\nnegate: 0\n"
                  "occupied_thresh: 0.65\nfree_thresh: 0.196\n", fs::path(m.pgm).filename().c_str(), res, x0, y0);
    y << buf;
    if (!img || !y) throw std::runtime_error(stem + ": cannot write the map");
  }

  // How well the walls sit where the scans end: end points (hits within the mapped range) on an occupied cell or
  // one of its 8 neighbours.
  std::uint64_t on = 0, total = 0;
  const auto occupied = [&](int cx, int cy) {
    if (cx < 0 || cy < 0 || cx >= m.width || cy >= m.height) return false;
    return cls[static_cast<std::size_t>(cy) * static_cast<std::size_t>(m.width) + static_cast<std::size_t>(cx)] ==
           kPgmOccupied;
  };
  for (const CarmenScan& s : scans) {
    const Frame f = frame_of(s.reference, mount);
    for (std::size_t k = 0; k < s.ranges.size(); ++k) {
      const double z = static_cast<double>(s.ranges[k]);
      if (!(z >= static_cast<double>(s.geometry.range_min_m)) || z >= static_cast<double>(s.geometry.range_max_m) ||
          z > o.max_range_m)
        continue;
      const double a = static_cast<double>(s.geometry.angle_min_rad) +
                       static_cast<double>(k) * static_cast<double>(s.geometry.angle_increment_rad);
      const double c = std::cos(a), sn = std::sin(a);
      const int cx = static_cast<int>(std::floor((f.x + z * (f.c * c - f.s * sn) - x0) / res));
      const int cy = static_cast<int>(std::floor((f.y + z * (f.s * c + f.c * sn) - y0) / res));
      bool hit = false;
      for (int dy = -1; dy <= 1 && !hit; ++dy)
        for (int dx = -1; dx <= 1 && !hit; ++dx) hit = occupied(cx + dx, cy + dy);
      on += hit ? 1 : 0;
      ++total;
    }
  }
  m.endpoints_on_walls = total > 0 ? static_cast<double>(on) / static_cast<double>(total) : 0.0;
  m.build_s = wall_seconds() - start;
  return m;
}

}  // namespace sim::data
