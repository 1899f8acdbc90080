#pragma once
// How far a ray caster's ranges are from the exact traversal's (GridRayCaster), over the same rays and scans for
// every caster: the accuracy checks of the cone caster and the heading range table.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "est/geometry/pose2.hpp"
#include "est/map/ray_casting.hpp"
#include "est/random/xoshiro128.hpp"
#include "est/sensor/beam_range_finder_model.hpp"
#include "est/sensor/range_scan.hpp"

namespace test_support {

struct Agreement {
  int rays = 0;
  int identical = 0;    // the same float as GridRayCaster
  int within_cell = 0;  // |caster - exact| <= one cell
  double worst = 0.0;   // m
};

inline void add(Agreement& s, float got, float exact, float cell) {
  const double d = std::fabs(double(got) - double(exact));
  ++s.rays;
  s.identical += got == exact ? 1 : 0;
  s.within_cell += d <= double(cell) ? 1 : 0;
  s.worst = std::max(s.worst, d);
}

struct TestRay {
  float x, y, dx, dy;
};

// Random starts in free cells, random headings (continuous, so never a table heading).
inline std::vector<TestRay> random_free_rays(const est::OccupancyGrid& g, int rays, std::uint64_t seed) {
  est::Rng rng(seed);
  std::vector<TestRay> out;
  while (static_cast<int>(out.size()) < rays) {
    const float x = g.origin_x() + rng.uniform(0.0f, static_cast<float>(g.width()) * g.resolution());
    const float y = g.origin_y() + rng.uniform(0.0f, static_cast<float>(g.height()) * g.resolution());
    const float th = rng.uniform(-est::kPi, est::kPi);
    std::int32_t cx = 0, cy = 0;
    if (!g.world_to_cell(x, y, cx, cy) || g.classify(cx, cy) != est::CellClass::free) continue;
    out.push_back({x, y, std::cos(th), std::sin(th)});
  }
  return out;
}

template <class Caster>
Agreement random_rays(const est::OccupancyGrid& g, const Caster& caster, int rays, float max_range,
                      std::uint64_t seed) {
  const est::GridRayCaster exact(g);
  Agreement s;
  for (const TestRay& r : random_free_rays(g, rays, seed))
    add(s, caster.cast(r.x, r.y, r.dx, r.dy, max_range), exact.cast(r.x, r.y, r.dx, r.dy, max_range),
        g.resolution());
  return s;
}

// The beam model with the book's default mixture at range limit `max_range` (ready() unless refused).
inline est::BeamRangeFinderModel beam_model(float max_range) {
  est::BeamModelParams bp;
  bp.range_max = max_range;
  est::BeamRangeFinderModel model;
  model.configure(bp);
  return model;
}

// A 360-beam scan over the full circle cast exactly from `truth` (range limit `max_range`), prepared into `scan`.
inline bool prepare_exact_scan(const est::OccupancyGrid& g, const est::Pose2& truth, float max_range,
                               est::PreparedScan<360>& scan) {
  const est::GridRayCaster exact(g);
  const est::ScanLayout layout{-est::kPi, est::kTwoPi / 360.0f, 360, 0.05f, max_range};
  std::vector<float> ranges(360);
  for (int k = 0; k < 360; ++k) {
    const float a = truth.theta + layout.angle_min + static_cast<float>(k) * layout.angle_increment;
    ranges[static_cast<std::size_t>(k)] = exact.cast(truth.x, truth.y, std::cos(a), std::sin(a), max_range);
  }
  return scan.prepare(layout, ranges.data(), 1) == est::ScanStatus::ok;
}

// Rays from every 7th free cell centre at multiples of 45 deg: through cell corners and along grid lines, where
// the traversal breaks ties.
template <class Caster>
Agreement centre_rays(const est::OccupancyGrid& g, const Caster& caster, float max_range) {
  const est::GridRayCaster exact(g);
  Agreement s;
  for (std::int32_t cy = 1; cy < g.height(); cy += 7) {
    for (std::int32_t cx = 1; cx < g.width(); cx += 7) {
      if (g.classify(cx, cy) != est::CellClass::free) continue;
      for (int k = 0; k < 8; ++k) {
        const float a = static_cast<float>(k) * est::kPi / 4.0f;
        const float dx = k % 2 == 0 ? std::round(std::cos(a)) : std::cos(a);
        const float dy = k % 2 == 0 ? std::round(std::sin(a)) : std::sin(a);
        const float x = g.cell_center_x(cx), y = g.cell_center_y(cy);
        add(s, caster.cast(x, y, dx, dy, max_range), exact.cast(x, y, dx, dy, max_range), g.resolution());
      }
    }
  }
  return s;
}

}  // namespace test_support
