#include "loop_world.hpp"

#include "est/map/distance_transform.hpp"
#include "est/math/fmath.hpp"
#include "est/random/samplers.hpp"

namespace est::selftest {
namespace {

OccupancyGridStorage<50, 40> g_grid;
DistanceTransformStorage<50, 40> g_edt;
LikelihoodField g_field;

}  // namespace

const Landmark kSmallLandmarks[kSmallLandmarkCount] = {{0.0f, 0.0f, 1.0f},  {5.0f, 0.0f, 2.0f},  {5.0f, 4.0f, 3.0f},
                                                       {0.0f, 4.0f, 4.0f},  {2.5f, -1.0f, 5.0f}, {2.5f, 5.0f, 6.0f}};

SmallMap small_map() {
  g_grid.configure(50, 40, 0.1f, 0.0f, 0.0f, kFreeCell);
  g_grid.fill_rect(0, 0, 49, 0, kOccupiedCell);
  g_grid.fill_rect(0, 39, 49, 39, kOccupiedCell);
  g_grid.fill_rect(0, 0, 0, 39, kOccupiedCell);
  g_grid.fill_rect(49, 0, 49, 39, kOccupiedCell);
  g_grid.fill_rect(30, 0, 30, 22, kOccupiedCell);
  g_grid.fill_rect(30, 22, 40, 22, kOccupiedCell);
  g_grid.fill_rect(8, 28, 12, 32, kOccupiedCell);
  const OccupancyGrid grid = g_grid.grid();
  g_edt.build(grid);
  LikelihoodFieldParams lf;
  lf.range_max = 6.0f;
  lf.max_distance = 1.0f;
  g_field.configure(lf, grid, g_edt.view());
  return SmallMap{grid, g_field, FreeSpaceSampler(grid, g_edt.view(), 0.15f), GridRayCaster(grid)};
}

ScanLayout small_scan_layout() {
  return ScanLayout{-kPi, kTwoPi / static_cast<float>(kSmallScanBeams), kSmallScanBeams, 0.05f, 6.0f};
}

void simulate_small_scan(const GridRayCaster& caster, const Pose2& truth, Rng& world,
                         float (&ranges)[kSmallScanBeams]) {
  for (int b = 0; b < kSmallScanBeams; ++b) {
    float s = 0.0f, c = 0.0f;
    fmath::sincos(truth.theta - kPi + static_cast<float>(b) * (kTwoPi / 60.0f), s, c);
    ranges[b] = caster.cast(truth.x, truth.y, c, s, 6.0f) + sample_normal(world, 0.02f);
  }
}

void sight_small_landmarks(const Pose2& truth, loop::TimeNs t, bool known, Rng& world,
                           loop::LandmarkInput (&out)[kSmallLandmarkCount]) {
  for (std::int32_t j = 0; j < kSmallLandmarkCount; ++j) {
    const float dx = kSmallLandmarks[j].x - truth.x, dy = kSmallLandmarks[j].y - truth.y;
    loop::LandmarkInput& z = out[j];
    z.t_ns = t;
    z.range_m = fmath::sqrt(dx * dx + dy * dy) + sample_normal(world, 0.05f);
    z.bearing_rad = fmath::normalize_angle(fmath::atan2(dy, dx) - truth.theta + sample_normal(world, 0.02f));
    z.signature = kSmallLandmarks[j].signature + sample_normal(world, 0.1f);
    z.id = known ? j : -1;
  }
}

}  // namespace est::selftest
