#include "world/office_map.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

namespace est::sim {

using est::OccupancyGridBuffer;
using est::MapStatus;
using est::kUnknownCell;
using est::kOccupiedCell;
using est::kFreeCell;

namespace {

std::int32_t cells(float metres) { return static_cast<std::int32_t>(std::lround(metres / kOfficeResolution)); }

// Axis-aligned block [x0, x1) x [y0, y1) in metres.
void block(OccupancyGridBuffer& g, float x0, float y0, float x1, float y1, std::uint8_t v = kOccupiedCell) {
  g.fill_rect(cells(x0), cells(y0), cells(x1) - 1, cells(y1) - 1, v);
}

}  // namespace

void make_office_map(OccupancyGridBuffer& g) {
  if (g.configure(kOfficeWidth, kOfficeHeight, kOfficeResolution, 0.0f, 0.0f, kFreeCell) != MapStatus::ok)
    throw std::runtime_error("make_office_map: the grid buffer is smaller than 400 x 300 cells");
  const float t = 0.1f;  // wall thickness
  // Outer walls.
  block(g, 0.0f, 0.0f, 20.0f, t);
  block(g, 0.0f, 15.0f - t, 20.0f, 15.0f);
  block(g, 0.0f, 0.0f, t, 15.0f);
  block(g, 20.0f - t, 0.0f, 20.0f, 15.0f);
  // Corridor along y in [6, 8.5]: walls with doors (1 m gaps).
  block(g, 0.0f, 6.0f, 3.0f, 6.0f + t);
  block(g, 4.0f, 6.0f, 9.0f, 6.0f + t);
  block(g, 10.0f, 6.0f, 20.0f, 6.0f + t);
  block(g, 0.0f, 8.5f, 5.0f, 8.5f + t);
  block(g, 6.0f, 8.5f, 14.0f, 8.5f + t);
  block(g, 15.0f, 8.5f, 20.0f, 8.5f + t);
  // Rooms south of the corridor (uneven widths) and north.
  block(g, 6.5f, 0.0f, 6.5f + t, 6.0f);
  block(g, 13.0f, 0.0f, 13.0f + t, 4.5f);
  block(g, 8.0f, 8.5f, 8.0f + t, 15.0f);
  block(g, 8.0f, 11.0f, 8.0f + t, 12.0f, kFreeCell);  // a door in it
  // Furniture: desks, a cabinet, an L-shaped counter.
  block(g, 1.0f, 1.0f, 2.6f, 1.8f);
  block(g, 3.5f, 3.0f, 5.0f, 3.8f);
  block(g, 9.0f, 2.0f, 11.5f, 2.6f);
  block(g, 15.0f, 1.0f, 19.0f, 1.6f);
  block(g, 18.4f, 1.6f, 19.0f, 4.0f);
  block(g, 10.0f, 12.5f, 12.0f, 14.0f);
  // A round pillar in the north-east room.
  const float px = 15.5f, py = 11.5f, pr = 0.6f;
  for (std::int32_t cy = cells(py - pr) - 1; cy <= cells(py + pr) + 1; ++cy)
    for (std::int32_t cx = cells(px - pr) - 1; cx <= cells(px + pr) + 1; ++cx) {
      const float dx = (static_cast<float>(cx) + 0.5f) * kOfficeResolution - px;
      const float dy = (static_cast<float>(cy) + 0.5f) * kOfficeResolution - py;
      if (dx * dx + dy * dy <= pr * pr) g.set(cx, cy, kOccupiedCell);
    }
  // A diagonal wall in the north-west room.
  for (std::int32_t i = 0; i <= 60; ++i) {
    const float x = 1.0f + 0.05f * static_cast<float>(i);
    const float y = 10.0f + 0.035f * static_cast<float>(i);
    g.fill_rect(cells(x), cells(y), cells(x) + 1, cells(y) + 1, kOccupiedCell);
  }
  // An unknown patch (never mapped): free space for the ray casters.
  block(g, 16.0f, 13.0f, 19.0f, 14.5f, kUnknownCell);
}

void make_office_landmarks(est::LandmarkMapBuffer& out) {
  const float posts[16][2] = {{0.5f, 8.0f},  {4.5f, 6.5f},  {8.5f, 8.1f},   {12.0f, 6.5f}, {17.0f, 8.0f}, {19.3f, 6.6f},
                              {13.5f, 9.0f}, {16.8f, 9.2f}, {11.0f, 11.0f}, {8.5f, 13.5f}, {7.5f, 9.2f},  {4.5f, 12.0f},
                              {2.0f, 9.0f},  {6.0f, 14.0f}, {18.5f, 12.5f}, {9.7f, 5.0f}};
  out.clear();
  for (int i = 0; i < 16; ++i) {
    const est::MapStatus s = out.add({posts[i][0], posts[i][1], static_cast<float>(i + 1)});
    if (s != est::MapStatus::ok) throw std::runtime_error("office landmarks: map status " + std::to_string(static_cast<int>(s)));
  }
}

}  // namespace est::sim
