// Ray casting and range finder models on the Intel map (or, without the shared datasets, a synthetic map of the same
// size): ns per beam for the exact and accelerated casters, ns per particle-beam for the beam and likelihood-field
// models, build time of the distance transform, and the memory of each structure.
//   build/host/bin/bench_sensor_models [--benchmark_filter=...]
// Measured (x86-64 2.6 GHz, -O3, CPU time on a loaded 2-core machine, Intel map, 180-beam scan, 30 m):
//   exact ray cast 230-240 ns/ray, distance-transform ray cast 150-180 ns/ray; distance transform build ~19 ms;
//   beam model ~140 ns per particle-beam with the exact caster, ~120 ns with the accelerated one (the cast
//   dominates; the density alone is ~11 ns); likelihood field ~3.4 ns per particle-beam.
// The exact cone caster (est/map/cone_ray_caster.hpp, 64 headings, 46 MiB, built in ~0.45 s), measured 2026-12-06
// on a quiet machine (CPU time, medians of 3), Intel map: beam model 92 ns per particle-beam against 144 (distance
// transform) and 218 (exact caster), the density alone 17 ns; side by side with the lane caster it replaced, 93
// against 105 ns. The cast from random free cells in random directions is slower than the exact caster's (463-616
// against 301-344 ns: no locality, cache misses in 46 MiB, and an atan2 per ray, where the beam model reads the
// table near its particle cloud and no atan2). With fixed-point jumps (2026-12-07), side by side with the float
// jumps in one session: beam model 56-59 against 86 ns per particle-beam. With the rays walked in AVX2 lanes and the
// densities in SSE2 lanes (2026-12-07, later), side by side: 3.9-4.3 against 10.0 us per particle of 180 beams
// (22-24 ns per particle-beam); packed 4.5. Without ../shared the map is a tiled synthetic office: set
// EST_SHARED_DIR=<the shared directory> to measure on the Intel map.
#include <benchmark/benchmark.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "est/map/cone_ray_caster.hpp"
#include "est/map/distance_transform.hpp"
#include "est/map/ray_casting.hpp"
#include "est/random/xoshiro128.hpp"
#include "est/sensor/beam_range_finder_model.hpp"
#include "est/sensor/beam_range_finder_model_cone.hpp"
#include "est/sensor/beam_readings.hpp"
#include "est/sensor/likelihood_field_range_finder_model.hpp"
#include "world/office_map.hpp"
#include "maps/ros_map_loader.hpp"

namespace {

est::OccupancyGridStorage<1024, 1024> g_grid;
est::DistanceTransformStorage<1024, 1024> g_edt;
est::PreparedScan<360> g_scan;
est::LikelihoodField g_field;
est::BeamRangeFinderModel g_beam;
std::string g_map_name;
// The cone caster (exact, cone_ray_caster.hpp): one byte per cell and heading.
constexpr std::int32_t kConeBins = 64;
est::ConeRayCasterStorage<64, 888, 848> g_cone;
est::ConeRayCasterStorage<64, 888, 848, 4> g_cone_packed;  // the same packed in 4 bits: half the memory
double g_cone_build_ms = 0.0;
est::BeamBearingsStorage<360> g_bearings;
est::BeamReadingsStorage<360> g_readings;

struct Ray {
  float x, y, dx, dy;
};
std::vector<Ray> g_rays;
std::vector<est::Pose2> g_particles;

void tile_office() {
  static est::OccupancyGridStorage<400, 300> office;
  est::sim::make_office_map(office);
  g_grid.configure(888, 848, 0.05f, 0.0f, 0.0f, est::kUnknownCell);
  for (std::int32_t y = 0; y < 848; ++y)
    for (std::int32_t x = 0; x < 888; ++x) g_grid.set(x, y, office.get(x % 400, y % 300));
}

bool random_free_point(est::Rng& rng, float& x, float& y) {
  const est::OccupancyGrid g = g_grid.grid();
  x = rng.uniform(0.0f, static_cast<float>(g.width()) * g.resolution());
  y = rng.uniform(0.0f, static_cast<float>(g.height()) * g.resolution());
  std::int32_t cx = 0, cy = 0;
  // Free and at least 0.3 m from a wall, like a robot's centre.
  return g.world_to_cell(x, y, cx, cy) && g.classify(cx, cy) == est::CellClass::free &&
         g_edt.view().metres(cx, cy) >= 0.3f;
}

void setup() {
  const std::string dir = est::sim::shared_datasets_dir();
  const std::string intel = dir + "/carmen-radish-logs/occupancy-maps-gondsm/intel.pgm";
  if (!dir.empty()) {
    est::sim::load_trinary_pgm_map(intel, g_grid);
    g_map_name = "Intel map 888 x 848 at 0.05 m";
  } else {
    tile_office();
    g_map_name = "synthetic office tiled to 888 x 848 at 0.05 m (no shared datasets)";
  }
  g_edt.build(g_grid.grid());
  const auto t0 = std::chrono::steady_clock::now();
  if (g_cone.build(g_grid.grid(), kConeBins) != est::ConeRayCasterStatus::ok)
    std::printf("cone caster build FAILED\n");
  g_cone_build_ms = 1e3 * std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (g_cone_packed.build(g_grid.grid(), kConeBins) != est::ConeRayCasterStatus::ok)
    std::printf("packed cone caster build FAILED\n");
  est::Rng rng(1u);
  while (g_rays.size() < 8192) {
    float x = 0.0f, y = 0.0f;
    if (!random_free_point(rng, x, y)) continue;
    const float th = rng.uniform(-est::kPi, est::kPi);
    g_rays.push_back({x, y, std::cos(th), std::sin(th)});
  }
  // A scan simulated at one free pose; particles spread around it.
  float x0 = 0.0f, y0 = 0.0f;
  while (!random_free_point(rng, x0, y0)) {
  }
  const est::DistanceTransformRayCaster caster(g_grid.grid(), g_edt.view());
  const est::ScanLayout layout{-est::kHalfPi, est::kPi / 180.0f, 180, 0.0f, 30.0f};
  float ranges[180];
  for (int k = 0; k < 180; ++k) {
    const float a = layout.angle_min + static_cast<float>(k) * layout.angle_increment;
    ranges[k] = caster.cast(x0, y0, std::cos(a), std::sin(a), 30.0f);
  }
  g_scan.prepare(layout, ranges);
  for (int i = 0; i < 1000; ++i)
    g_particles.push_back({x0 + rng.uniform(-1.0f, 1.0f), y0 + rng.uniform(-1.0f, 1.0f), rng.uniform(-0.5f, 0.5f)});
  est::BeamModelParams bp;
  bp.range_max = 30.0f;
  g_beam.configure(bp);
  g_bearings.prepare(g_scan.beams(), kConeBins);
  g_readings.prepare(g_scan.beams(), g_beam);
  est::LikelihoodFieldParams lp;
  lp.range_max = 30.0f;
  g_field.configure(lp, g_grid.grid(), g_edt.view());
}

template <class Caster>
void cast_rays(benchmark::State& state, const Caster& caster) {
  const float max_range = static_cast<float>(state.range(0));
  std::size_t i = 0;
  for (auto _ : state) {
    const Ray& r = g_rays[i++ & 8191];
    benchmark::DoNotOptimize(caster.cast(r.x, r.y, r.dx, r.dy, max_range));
  }
  state.SetItemsProcessed(state.iterations());
}

void BM_RayCastExact(benchmark::State& state) { cast_rays(state, est::GridRayCaster(g_grid.grid())); }
void BM_RayCastDistanceTransform(benchmark::State& state) {
  cast_rays(state, est::DistanceTransformRayCaster(g_grid.grid(), g_edt.view()));
}
void BM_RayCastCone(benchmark::State& state) { cast_rays(state, g_cone.view()); }
BENCHMARK(BM_RayCastCone)->Arg(5)->Arg(10)->Arg(30);
BENCHMARK(BM_RayCastExact)->Arg(5)->Arg(10)->Arg(30);
BENCHMARK(BM_RayCastDistanceTransform)->Arg(5)->Arg(10)->Arg(30);

void BM_DistanceTransformBuild(benchmark::State& state) {
  for (auto _ : state) benchmark::DoNotOptimize(g_edt.build(g_grid.grid()));
}
BENCHMARK(BM_DistanceTransformBuild)->Unit(benchmark::kMillisecond);

// One particle per iteration, K = 180 beams: items are particle-beams.
template <class Caster>
void beam_model(benchmark::State& state, const Caster& caster) {
  const est::ScanBeams b = g_scan.beams();
  std::size_t i = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(est::beam_range_finder_model(b, g_particles[i++ % 1000], {}, caster, g_beam));
  }
  state.SetItemsProcessed(state.iterations() * b.count);
}
void BM_BeamModelExactCaster(benchmark::State& state) { beam_model(state, est::GridRayCaster(g_grid.grid())); }
void BM_BeamModelDistanceTransformCaster(benchmark::State& state) {
  beam_model(state, est::DistanceTransformRayCaster(g_grid.grid(), g_edt.view()));
}
// The cone caster through its beam-model overload: bearings and readings prepared once per scan, no atan2 per beam,
// the densities multiplied (beam_range_finder_model_cone.hpp). Exact: the same z* as the exact caster.
template <class Cone>
void beam_model_cone(benchmark::State& state, const Cone& cone) {
  const est::ScanBeams b = g_scan.beams();
  std::size_t i = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(est::beam_range_finder_model(b, g_bearings.view(), g_readings.view(),
                                                          g_particles[i++ % 1000], {}, cone, g_beam));
  }
  state.SetItemsProcessed(state.iterations() * b.count);
}
BENCHMARK(BM_BeamModelExactCaster);
BENCHMARK(BM_BeamModelDistanceTransformCaster);
void BM_BeamModelCone(benchmark::State& state) { beam_model_cone(state, g_cone.view()); }
void BM_BeamModelConePacked(benchmark::State& state) { beam_model_cone(state, g_cone_packed.view()); }
BENCHMARK(BM_BeamModelCone);
BENCHMARK(BM_BeamModelConePacked);

void BM_BeamModelDensityOnly(benchmark::State& state) {
  float z = 0.0f;
  for (auto _ : state) {
    z += 0.013f;
    if (z > 30.0f) z = 0.0f;
    benchmark::DoNotOptimize(g_beam.log_density(z, 7.0f));
  }
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_BeamModelDensityOnly);

void BM_LikelihoodField(benchmark::State& state) {
  const est::ScanBeams b = g_scan.beams();
  std::size_t i = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(est::likelihood_field_range_finder_model(b, g_particles[i++ % 1000], {}, g_field));
  }
  state.SetItemsProcessed(state.iterations() * b.count);
}
BENCHMARK(BM_LikelihoodField);

}  // namespace

int main(int argc, char** argv) {
  setup();
  std::printf("map: %s\n", g_map_name.c_str());
  std::printf("memory: occupancy grid 1 byte/cell = %d bytes used (storage <1024, 1024>: %u bytes)\n",
              g_grid.grid().cell_count(), est::OccupancyGridStorage<1024, 1024>::kBytes);
  std::printf("memory: distance transform 2 bytes/cell = %d bytes used (storage <1024, 1024>: %u bytes incl. scratch)\n",
              2 * g_grid.grid().cell_count(), est::DistanceTransformStorage<1024, 1024>::kBytes);
  std::printf("memory: likelihood field table %zu bytes (%d entries used), shares the distance transform\n",
              sizeof(est::LikelihoodField), g_field.table_entries());
  {
    const est::GridRayCaster exact(g_grid.grid());
    const est::ConeRayCaster cone = g_cone.view();
    int same = 0, within = 0, n = 0;
    float worst = 0.0f;
    for (const Ray& r : g_rays) {
      const float a = exact.cast(r.x, r.y, r.dx, r.dy, 30.0f), c = cone.cast(r.x, r.y, r.dx, r.dy, 30.0f);
      ++n;
      same += a == c;
      within += std::fabs(a - c) <= 0.05f;
      worst = std::fmax(worst, std::fabs(a - c));
    }
    std::printf("memory: cone caster, %d headings: %.1f MiB, built in %.0f ms; %d of %d random rays the same float "
                "as the exact caster, %d within a cell, worst %.3f m\n",
                kConeBins, static_cast<double>(g_cone.bytes_used()) / 1048576.0, g_cone_build_ms, same, n, within,
                static_cast<double>(worst));
    std::printf("memory: packed cone caster (4 bits), %d headings: %.1f MiB\n", kConeBins,
                static_cast<double>(g_cone_packed.bytes_used()) / 1048576.0);
  }
  std::printf("memory: prepared scan <360> %zu bytes, beam model %zu bytes\n", sizeof(est::PreparedScan<360>),
              sizeof(est::BeamRangeFinderModel));
  std::printf("scan: %d beams kept, %d max readings; items below are rays (casters) or particle-beams (models)\n",
              g_scan.beams().count, g_scan.counters().max_readings);
  benchmark::Initialize(&argc, argv);
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
