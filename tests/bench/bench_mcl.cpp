// Monte Carlo localization stages on the Intel lab map (or, without the shared datasets, a synthetic map of the same
// size, said in the output): predict, weight (beam model with the distance-transform ray caster, the exact cone caster
// and the heading lookup table, the last two with prepared readings; likelihood field, batched and scalar) and
// resample, for N particles and K beams
// (default N = 256 .. 65536 by 4, K = 60 and 360; the exact-casting beam model to N = 16384, its cost being 100x);
// then the machine, a summary in ns per particle / particle-beam against the project's targets (issue 14) and the
// peers' figures, and the memory of every acceleration structure. Per-thread CPU time; figures only, nothing is
// asserted.
//   build/host/bin/bench_mcl [--n=256,4096,65536] [--k=60,360] [--map=FILE.pgm|office] [--benchmark_filter=...]
//     [--benchmark_repetitions=3 --benchmark_report_aggregates_only=true]: the summary then takes each run's median.
//   K must divide 360 (every 360/K-th beam of the scan); --map takes a trinary PGM at 0.05 m (as the Intel map) of
//   at most 1024 x 1024 cells, or the synthetic office; the default is the Intel map of the shared datasets.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "est/filter/augmented_mcl.hpp"
#include "est/filter/free_space_sampler.hpp"
#include "est/map/distance_transform.hpp"
#include "est/map/cone_ray_caster.hpp"
#include "est/map/heading_range_table.hpp"
#include "est/map/ray_casting.hpp"
#include "est/motion/bicycle_model.hpp"
#include "est/motion/diff_drive_model.hpp"
#include "est/motion/motion_batch.hpp"
#include "est/sensor/beam_range_finder_model.hpp"
#include "est/sensor/beam_range_finder_model_cone.hpp"
#include "est/sensor/beam_range_finder_model_table.hpp"
#include "est/sensor/beam_readings.hpp"
#include "est/sensor/likelihood_field_grid.hpp"
#include "est/sensor/likelihood_field_range_finder_model.hpp"
#include "est/sensor/range_scan.hpp"
#include "world/office_map.hpp"
#include "maps/ros_map_loader.hpp"

namespace {

constexpr std::uint32_t kNMax = 65536;
constexpr float kRangeMax = 20.0f;

est::OccupancyGridStorage<1024, 1024> g_grid;
est::DistanceTransformStorage<1024, 1024> g_edt;
est::LikelihoodFieldGridStorage<1024, 1024> g_field_grid;
// The beam model's lookup table: 64 headings (5.6 deg) per cell, sized for the 888 x 848 map (92 MiB).
constexpr std::int32_t kTableBins = 64;
est::HeadingRangeTableStorage<888, 848, kTableBins> g_table;
// The exact beam model's cone caster at as many headings: 1 B per cell and heading (46 MiB), the same bearings.
est::ConeRayCasterStorage<kTableBins, 888, 848> g_cone;
// Per K (every 360/K-th beam of the 360-beam scan): the prepared scan, bearings and readings.
std::map<std::int64_t, std::unique_ptr<est::PreparedScan<360>>> g_scans;
std::map<std::int64_t, std::unique_ptr<est::BeamBearingsStorage<360>>> g_bearings;
std::map<std::int64_t, std::unique_ptr<est::BeamReadingsStorage<360>>> g_readings;
// The sweep (command line): particle counts, beam counts, the map.
std::vector<std::int64_t> g_ns = {256, 1024, 4096, 16384, 65536};
std::vector<std::int64_t> g_ks = {60, 360};
std::string g_map_arg;
constexpr std::int64_t kBeamExactMaxN = 16384;  // the exact-casting beam model only up to here (100x the cost)
est::LikelihoodField g_field;
est::BeamRangeFinderModel g_beam;
std::string g_map_name;
est::Pose2 g_truth;
float g_mean_range = 0.0f;
double g_edt_build_ms = 0.0, g_field_grid_build_ms = 0.0, g_table_build_ms = 0.0, g_cone_build_ms = 0.0;

// The table's range error against the exact traversal, from random free cells in random directions.
struct TableError {
  int rays = 0;
  double mean = 0.0, p50 = 0.0, p90 = 0.0, p99 = 0.0, max = 0.0, within_10cm = 0.0, within_sigma = 0.0;
  double exact_ns = 0.0, dt_ns = 0.0, table_ns = 0.0, cone_ns = 0.0;
  int cone_identical = 0, cone_within_cell = 0;  // the cone caster's rays: the same float as the exact, within a cell
};
TableError g_table_error;

using Mcl = est::AugmentedMcl<kNMax>;
std::unique_ptr<Mcl> g_mcl;
std::unique_ptr<Mcl> g_mcl_kld;  // KLD-adaptive, floor 500 (the simulator's)

void tile_office() {
  static est::OccupancyGridStorage<400, 300> office;
  est::sim::make_office_map(office);
  g_grid.configure(888, 848, 0.05f, 0.0f, 0.0f, est::kUnknownCell);
  for (std::int32_t y = 0; y < 848; ++y)
    for (std::int32_t x = 0; x < 888; ++x) g_grid.set(x, y, office.get(x % 400, y % 300));
}

double ms_since(const std::chrono::steady_clock::time_point& t0) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

void setup() {
  const std::string dir = est::sim::shared_datasets_dir();
  const std::string intel = !g_map_arg.empty() && g_map_arg != "office"
                                ? g_map_arg
                                : dir + "/carmen-radish-logs/occupancy-maps-gondsm/intel.pgm";
  bool loaded = false;
  if ((!dir.empty() || !g_map_arg.empty()) && g_map_arg != "office") {
    try {
      est::sim::load_trinary_pgm_map(intel, g_grid);
      g_map_name = (g_map_arg.empty() ? "Intel lab map (" : "map (") + intel + "), " +
                   std::to_string(g_grid.grid().width()) + " x " + std::to_string(g_grid.grid().height()) +
                   " at 0.05 m";
      loaded = true;
    } catch (const std::exception& e) {
      std::printf("could not load the map: %s\n", e.what());
    }
  }
  if (!loaded) {
    tile_office();
    g_map_name = "SYNTHETIC office tiled to 888 x 848 at 0.05 m (shared datasets absent: not the Intel map)";
  }
  auto t0 = std::chrono::steady_clock::now();
  g_edt.build(g_grid.grid());
  g_edt_build_ms = ms_since(t0);
  est::LikelihoodFieldParams lp;
  lp.range_max = kRangeMax;
  g_field.configure(lp, g_grid.grid(), g_edt.view());
  t0 = std::chrono::steady_clock::now();
  g_field_grid.build(g_field, g_grid.grid());
  g_field_grid_build_ms = ms_since(t0);
  t0 = std::chrono::steady_clock::now();
  // Built with the distance-transform caster: the same ranges as the exact traversal (test_ray_casting), faster.
  const est::HeadingRangeTableStatus ts = g_table.build(
      g_grid.grid(), est::DistanceTransformRayCaster(g_grid.grid(), g_edt.view()), kTableBins, kRangeMax);
  g_table_build_ms = ms_since(t0);
  if (ts != est::HeadingRangeTableStatus::ok) std::printf("heading table build FAILED (%d)\n", static_cast<int>(ts));
  t0 = std::chrono::steady_clock::now();
  const est::ConeRayCasterStatus cs = g_cone.build(g_grid.grid(), kTableBins);
  g_cone_build_ms = ms_since(t0);
  if (cs != est::ConeRayCasterStatus::ok) std::printf("cone caster build FAILED (%d)\n", static_cast<int>(cs));
  est::BeamModelParams bp;
  bp.range_max = kRangeMax;
  g_beam.configure(bp);

  // The scan: 360 beams cast exactly from a free pose >= 0.5 m from walls whose mean range is the closest to the
  // peers' workload (6.8 m) among 200 candidates, with 2 cm noise.
  const est::FreeSpaceSampler free_space(g_grid.grid(), g_edt.view(), 0.5f, 1000u);
  const est::GridRayCaster exact(g_grid.grid());
  const est::ScanLayout layout{-est::kPi, est::kTwoPi / 360.0f, 360, 0.05f, kRangeMax};
  est::Rng rng(1u);
  std::vector<float> best, ranges(360);
  float best_gap = 1e9f;
  for (int c = 0; c < 200; ++c) {
    est::Pose2 p;
    if (!free_space(rng, p)) continue;
    float sum = 0.0f;
    for (int k = 0; k < 360; ++k) {
      const float a = p.theta + layout.angle_min + static_cast<float>(k) * layout.angle_increment;
      ranges[static_cast<std::size_t>(k)] = exact.cast(p.x, p.y, std::cos(a), std::sin(a), kRangeMax);
      sum += ranges[static_cast<std::size_t>(k)];
    }
    const float mean = sum / 360.0f;
    if (std::fabs(mean - 6.8f) < best_gap) {
      best_gap = std::fabs(mean - 6.8f);
      best = ranges;
      g_truth = p;
      g_mean_range = mean;
    }
  }
  for (float& z : best) z += est::sample_normal(rng, 0.02f);
  for (const std::int64_t k : g_ks) {
    g_scans[k] = std::make_unique<est::PreparedScan<360>>();
    g_scans[k]->prepare(layout, best.data(), static_cast<std::int32_t>(360 / k));
    g_bearings[k] = std::make_unique<est::BeamBearingsStorage<360>>();
    g_bearings[k]->prepare(g_scans[k]->beams(), g_table.view());
    g_readings[k] = std::make_unique<est::BeamReadingsStorage<360>>();
    g_readings[k]->prepare(g_scans[k]->beams(), g_beam);
  }

  // Range error of the table against the exact traversal: 20 000 rays, 20 m, from random free cells.
  {
    const est::HeadingRangeTable table = g_table.view();
    const est::DistanceTransformRayCaster dt(g_grid.grid(), g_edt.view());
    const est::OccupancyGrid g = g_grid.grid();
    std::vector<double> err;
    std::vector<float> xs, ys, dxs, dys, sink(3);
    est::Rng erng(99u);
    while (err.size() < 20000) {
      const float x = g.origin_x() + erng.uniform(0.0f, static_cast<float>(g.width()) * g.resolution());
      const float y = g.origin_y() + erng.uniform(0.0f, static_cast<float>(g.height()) * g.resolution());
      const float th = erng.uniform(-est::kPi, est::kPi);
      std::int32_t cx = 0, cy = 0;
      if (!g.world_to_cell(x, y, cx, cy) || g.classify(cx, cy) != est::CellClass::free) continue;
      const float dx = std::cos(th), dy = std::sin(th);
      const float want = exact.cast(x, y, dx, dy, kRangeMax), cone = g_cone.view().cast(x, y, dx, dy, kRangeMax);
      err.push_back(std::fabs(double(table.cast(x, y, dx, dy, kRangeMax)) - double(want)));
      g_table_error.cone_identical += std::memcmp(&want, &cone, sizeof want) == 0 ? 1 : 0;
      g_table_error.cone_within_cell += std::fabs(want - cone) <= g.resolution() ? 1 : 0;
      xs.push_back(x);
      ys.push_back(y);
      dxs.push_back(dx);
      dys.push_back(dy);
    }
    TableError& e = g_table_error;
    e.rays = static_cast<int>(err.size());
    for (double v : err) {
      e.mean += v / e.rays;
      e.within_10cm += v <= 0.10 ? 1.0 / e.rays : 0.0;
      e.within_sigma += v <= 0.2 ? 1.0 / e.rays : 0.0;
    }
    std::sort(err.begin(), err.end());
    e.p50 = err[err.size() / 2];
    e.p90 = err[err.size() * 9 / 10];
    e.p99 = err[err.size() * 99 / 100];
    e.max = err.back();
    // Per-ray cost of each caster over the same rays (clock read once per pass).
    auto per_ray = [&](auto&& cast) {
      const auto c0 = std::chrono::steady_clock::now();
      float acc = 0.0f;
      for (int rep = 0; rep < 5; ++rep)
        for (std::size_t i = 0; i < xs.size(); ++i) acc += cast(xs[i], ys[i], dxs[i], dys[i]);
      sink[0] += acc;
      return 1e6 * ms_since(c0) / (5.0 * static_cast<double>(xs.size()));
    };
    e.exact_ns = per_ray([&](float x, float y, float dx, float dy) { return exact.cast(x, y, dx, dy, kRangeMax); });
    e.dt_ns = per_ray([&](float x, float y, float dx, float dy) { return dt.cast(x, y, dx, dy, kRangeMax); });
    e.table_ns = per_ray([&](float x, float y, float dx, float dy) { return table.cast(x, y, dx, dy, kRangeMax); });
    const est::ConeRayCaster cone = g_cone.view();
    e.cone_ns = per_ray([&](float x, float y, float dx, float dy) { return cone.cast(x, y, dx, dy, kRangeMax); });
    benchmark::DoNotOptimize(sink[0]);
  }
  est::MclConfig cfg;
  cfg.recovery = false;
  g_mcl = std::make_unique<Mcl>(cfg, 7u);
  cfg.kld = true;
  cfg.kld_config.n_min = 500;
  g_mcl_kld = std::make_unique<Mcl>(cfg, 8u);
}

// A tracking cloud around the scan's pose: 0.3 m and 0.1 rad.
Mcl& cloud(std::uint32_t n) {
  g_mcl->initialize_gaussian(g_truth, 0.3f, 0.1f, n);
  return *g_mcl;
}
est::ScanBeams scan(std::int64_t k) { return g_scans.at(k)->beams(); }

void set_items(benchmark::State& state, std::int64_t per_iteration) {
  state.SetItemsProcessed(state.iterations() * per_iteration);
}

est::BicycleParams bicycle_params() {
  est::BicycleParams p;
  p.frame_length = 0.6f;
  p.steer_sigma = 0.04f;
  p.speed_var_per_speed = 0.008f;
  p.final_rot_sigma = 0.01f;
  return p;
}
est::DiffDriveParams diff_drive_params() {
  est::DiffDriveParams p;
  p.travel_sigma_per_m = 0.05f;
  p.travel_sigma_floor = 0.001f;
  p.final_rot_sigma = 0.01f;
  return p;
}
constexpr est::BicycleControl kBicycleU{0.8f, 0.1f};
constexpr est::DiffDriveControl kDiffDriveU{1000, 1100};

// Per particle: the model's own sampler (Box-Muller, one of each pair kept, fmath's full-range trigonometry).
void BM_predict_bicycle(benchmark::State& state) {
  const auto n = static_cast<std::uint32_t>(state.range(0));
  Mcl& mcl = cloud(n);
  const est::BicycleParams p = bicycle_params();
  for (auto _ : state) mcl.predict<est::BicycleMotionModel>(kBicycleU, p);
  set_items(state, n);
}
void BM_predict_diff_drive(benchmark::State& state) {
  const auto n = static_cast<std::uint32_t>(state.range(0));
  Mcl& mcl = cloud(n);
  const est::DiffDriveParams p = diff_drive_params();
  for (auto _ : state) mcl.predict<est::DiffDriveMotionModel>(kDiffDriveU, p);
  set_items(state, n);
}
// The whole set at once (est/motion/motion_batch.hpp): noise in bulk, both Box-Muller halves, inline trigonometry.
void BM_predict_bicycle_batch(benchmark::State& state) {
  const auto n = static_cast<std::uint32_t>(state.range(0));
  Mcl& mcl = cloud(n);
  const est::BicycleParams p = bicycle_params();
  for (auto _ : state) mcl.predict_batch<est::BicycleMotionModel>(kBicycleU, p);
  set_items(state, n);
}
void BM_predict_diff_drive_batch(benchmark::State& state) {
  const auto n = static_cast<std::uint32_t>(state.range(0));
  Mcl& mcl = cloud(n);
  const est::DiffDriveParams p = diff_drive_params();
  for (auto _ : state) mcl.predict_batch<est::DiffDriveMotionModel>(kDiffDriveU, p);
  set_items(state, n);
}

void BM_weight_likelihood_field(benchmark::State& state) {
  const auto n = static_cast<std::uint32_t>(state.range(0));
  const est::ScanBeams z = scan(state.range(1));
  Mcl& mcl = cloud(n);
  const est::LikelihoodFieldGrid field = g_field_grid.view();
  for (auto _ : state) {
    mcl.correct_batch([&](est::ConstParticleSetView p, float* out) {
      est::likelihood_field_range_finder_model_batch(z, p.x, p.y, p.theta, p.count, {}, field, out);
    });
  }
  set_items(state, static_cast<std::int64_t>(n) * z.count);
}

void BM_weight_likelihood_field_scalar(benchmark::State& state) {
  const auto n = static_cast<std::uint32_t>(state.range(0));
  const est::ScanBeams z = scan(state.range(1));
  Mcl& mcl = cloud(n);
  for (auto _ : state)
    mcl.correct([&](const est::Pose2& x) { return est::likelihood_field_range_finder_model(z, x, {}, g_field); });
  set_items(state, static_cast<std::int64_t>(n) * z.count);
}

void BM_weight_beam(benchmark::State& state) {
  const auto n = static_cast<std::uint32_t>(state.range(0));
  const est::ScanBeams z = scan(state.range(1));
  Mcl& mcl = cloud(n);
  const est::DistanceTransformRayCaster caster(g_grid.grid(), g_edt.view());
  for (auto _ : state)
    mcl.correct([&](const est::Pose2& x) { return est::beam_range_finder_model(z, x, {}, caster, g_beam); });
  set_items(state, static_cast<std::int64_t>(n) * z.count);
}

// z* by a caster over heading bins, bearings and readings prepared once per scan, the beams' densities multiplied
// and taken to log space once per particle (est/sensor/beam_range_finder_model_table.hpp).
template <class BinCaster>
void weight_beam_bins(benchmark::State& state, const BinCaster& caster) {
  const auto n = static_cast<std::uint32_t>(state.range(0));
  const est::ScanBeams z = scan(state.range(1));
  const est::BeamBearings bearings = g_bearings.at(state.range(1))->view();
  const est::BeamReadings readings = g_readings.at(state.range(1))->view();
  Mcl& mcl = cloud(n);
  auto weigh = [&](const est::Pose2& x) {
    return est::beam_range_finder_model(z, bearings, readings, x, {}, caster, g_beam);
  };
  for (auto _ : state) mcl.correct(weigh);
  set_items(state, static_cast<std::int64_t>(n) * z.count);
}
// z* from the heading lookup table (approximate).
void BM_weight_beam_table(benchmark::State& state) { weight_beam_bins(state, g_table.view()); }
// z* cast exactly by the cone caster (the same floats as the exact traversal; on an AVX2 host a particle's rays are
// walked together in lanes, est/map/cone_ray_caster.hpp).
void BM_weight_beam_cone(benchmark::State& state) { weight_beam_bins(state, g_cone.view()); }

void BM_resample(benchmark::State& state) {
  const auto n = static_cast<std::uint32_t>(state.range(0));
  Mcl& mcl = cloud(n);
  const est::FreeSpaceSampler free_space(g_grid.grid(), g_edt.view(), 0.2f);
  // Unequal weights, as after a correction (resampling cost does not depend on them beyond the copy pattern).
  const est::ScanBeams z = scan(g_ks.front());
  mcl.correct([&](const est::Pose2& x) { return est::likelihood_field_range_finder_model(z, x, {}, g_field); });
  for (auto _ : state) mcl.resample(free_space, true);
  set_items(state, n);
}

// KLD resampling (table 8.4: i.i.d. draws until n >= n_chi(k), a binary search each, then the low-variance comb)
// of a corrected tracking cloud of N particles; the weighted set is rebuilt outside the timing each iteration.
void BM_resample_kld(benchmark::State& state) {
  const auto n = static_cast<std::uint32_t>(state.range(0));
  Mcl& mcl = *g_mcl_kld;
  const est::FreeSpaceSampler free_space(g_grid.grid(), g_edt.view(), 0.2f);
  const est::ScanBeams z = scan(g_ks.front());
  std::uint64_t drawn = 0;
  for (auto _ : state) {
    state.PauseTiming();
    mcl.initialize_gaussian(g_truth, 0.3f, 0.1f, n);
    mcl.correct([&](const est::Pose2& x) { return est::likelihood_field_range_finder_model(z, x, {}, g_field); });
    const std::uint32_t before = mcl.counters().drawn_particles;
    state.ResumeTiming();
    mcl.resample(free_space, true);
    drawn += mcl.counters().drawn_particles - before;
  }
  state.counters["drawn"] = static_cast<double>(drawn) / static_cast<double>(state.iterations());
  set_items(state, n);
}

void particle_args(benchmark::internal::Benchmark* b) {
  for (std::int64_t n : g_ns) b->Arg(n);
}
void particle_beam_args(benchmark::internal::Benchmark* b) {
  for (std::int64_t k : g_ks)
    for (std::int64_t n : g_ns) b->Args({n, k});
}
void particle_beam_args_exact(benchmark::internal::Benchmark* b) {
  for (std::int64_t k : g_ks)
    for (std::int64_t n : g_ns)
      if (n <= kBeamExactMaxN) b->Args({n, k});
}
// Registered after the command line is read (the sweep's sizes come from it).
void register_benchmarks() {
  using benchmark::RegisterBenchmark;
  RegisterBenchmark("BM_predict_bicycle", BM_predict_bicycle)->Apply(particle_args)->Unit(benchmark::kMicrosecond);
  RegisterBenchmark("BM_predict_diff_drive", BM_predict_diff_drive)
      ->Apply(particle_args)
      ->Unit(benchmark::kMicrosecond);
  RegisterBenchmark("BM_predict_bicycle_batch", BM_predict_bicycle_batch)
      ->Apply(particle_args)
      ->Unit(benchmark::kMicrosecond);
  RegisterBenchmark("BM_predict_diff_drive_batch", BM_predict_diff_drive_batch)
      ->Apply(particle_args)
      ->Unit(benchmark::kMicrosecond);
  RegisterBenchmark("BM_weight_likelihood_field", BM_weight_likelihood_field)
      ->Apply(particle_beam_args)
      ->Unit(benchmark::kMicrosecond);
  RegisterBenchmark("BM_weight_likelihood_field_scalar", BM_weight_likelihood_field_scalar)
      ->Apply(particle_beam_args)
      ->Unit(benchmark::kMicrosecond);
  RegisterBenchmark("BM_weight_beam", BM_weight_beam)
      ->Apply(particle_beam_args_exact)
      ->Unit(benchmark::kMicrosecond)
      ->MinTime(0.2);
  RegisterBenchmark("BM_weight_beam_table", BM_weight_beam_table)
      ->Apply(particle_beam_args)
      ->Unit(benchmark::kMicrosecond);
  RegisterBenchmark("BM_weight_beam_cone", BM_weight_beam_cone)
      ->Apply(particle_beam_args)
      ->Unit(benchmark::kMicrosecond);
  RegisterBenchmark("BM_resample", BM_resample)->Apply(particle_args)->Unit(benchmark::kMicrosecond);
  RegisterBenchmark("BM_resample_kld", BM_resample_kld)->Apply(particle_args)->Unit(benchmark::kMicrosecond);
}

// --n=, --k=, --map= (removed from argv before Google Benchmark reads the rest). False on a bad value.
bool parse_list(const char* text, std::vector<std::int64_t>& out) {
  out.clear();
  std::string item;
  for (const char* c = text;; ++c) {
    if (*c == ',' || *c == '\0') {
      if (item.empty()) return false;
      char* end = nullptr;
      const long long v = std::strtoll(item.c_str(), &end, 10);
      if (end == nullptr || *end != '\0' || v <= 0) return false;
      out.push_back(v);
      item.clear();
      if (*c == '\0') break;
    } else {
      item += *c;
    }
  }
  return !out.empty();
}
bool parse_arguments(int& argc, char** argv) {
  int kept = 1;
  for (int i = 1; i < argc; ++i) {
    const char* a = argv[i];
    bool ok = true;
    if (std::strncmp(a, "--n=", 4) == 0) {
      ok = parse_list(a + 4, g_ns);
      for (const std::int64_t n : g_ns) ok = ok && n <= static_cast<std::int64_t>(kNMax);
    } else if (std::strncmp(a, "--k=", 4) == 0) {
      ok = parse_list(a + 4, g_ks);
      for (const std::int64_t k : g_ks) ok = ok && k <= 360 && 360 % k == 0;
    } else if (std::strncmp(a, "--map=", 6) == 0) {
      g_map_arg = a + 6;
      ok = !g_map_arg.empty();
    } else {
      argv[kept++] = argv[i];
      continue;
    }
    if (!ok) {
      std::fprintf(stderr, "bench_mcl: bad argument '%s' (--n=N[,N...] with N <= %u; --k=K[,K...] with K dividing"
                           " 360; --map=FILE.pgm or office)\n", a, kNMax);
      return false;
    }
  }
  argc = kept;
  return true;
}

// The machine the figures come from: CPU model, logical CPUs, compiler.
void print_machine() {
  std::string model = "unknown CPU";
  std::ifstream cpu("/proc/cpuinfo");
  std::string line;
  int cpus = 0;
  while (std::getline(cpu, line)) {
    if (line.rfind("model name", 0) == 0 && model == "unknown CPU") model = line.substr(line.find(':') + 2);
    if (line.rfind("processor", 0) == 0) ++cpus;
  }
  std::printf("machine: %s, %d logical CPUs (one used), compiler %s, -O3 -ffp-contract=off, x86-64 baseline (SSE2;\n"
              "  the particle loops four lanes wide, est/math/lanes.hpp); AVX2 %s (the cone caster's rays %s)\n",
              model.c_str(), cpus, __VERSION__, est::ConeRayCaster::lanes_vectorized() ? "yes" : "no",
              est::ConeRayCaster::lanes_vectorized() ? "eight lanes wide" : "one at a time");
}

// Keeps every run's CPU time per item (ns) for the summary; with --benchmark_repetitions the median of the
// repetitions (also under --benchmark_report_aggregates_only).
class Collector : public benchmark::ConsoleReporter {
 public:
  std::map<std::string, double> ns_per_item, median_ns_per_item;
  void ReportRuns(const std::vector<Run>& runs) override {
    for (const Run& r : runs) {
      if (r.error_occurred) continue;
      const bool median = r.run_type == Run::RT_Aggregate && r.aggregate_name == "median";
      if (r.run_type != Run::RT_Iteration && !median) continue;
      const auto it = r.counters.find("items_per_second");
      std::string name = r.run_name.str();
      const auto cut = name.find("/min_time:");
      if (cut != std::string::npos) name.erase(cut);
      if (it != r.counters.end() && it->second.value > 0.0)
        (median ? median_ns_per_item : ns_per_item)[name] = 1e9 / it->second.value;
    }
    ConsoleReporter::ReportRuns(runs);
  }
};

double get(const Collector& c, const std::string& name) {
  const auto m = c.median_ns_per_item.find(name);
  if (m != c.median_ns_per_item.end()) return m->second;
  const auto it = c.ns_per_item.find(name);
  return it == c.ns_per_item.end() ? -1.0 : it->second;
}

// The largest per-item cost of a stage over every N (and K).
double worst(const Collector& c, const std::string& stem, bool with_k) {
  double hi = -1.0;
  for (const std::int64_t k : g_ks) {
    for (const std::int64_t n : g_ns)
      hi = std::max(hi, get(c, stem + "/" + std::to_string(n) + (with_k ? "/" + std::to_string(k) : "")));
    if (!with_k) break;
  }
  return hi;
}

const char* verdict(double v, double target) { return v < 0.0 ? "not run" : (v <= target ? "MET" : "NOT MET"); }

// max / min of the per-item cost over the sizes: 1 is perfectly linear in N x K.
double spread(const Collector& c, const std::string& stem, bool with_k) {
  double lo = 1e300, hi = 0.0;
  for (const std::int64_t k : g_ks) {
    if (!with_k && k != g_ks.front()) break;
    for (const std::int64_t n : g_ns) {
      const double v = get(c, stem + "/" + std::to_string(n) + (with_k ? "/" + std::to_string(k) : ""));
      if (v <= 0.0) continue;
      lo = std::min(lo, v);
      hi = std::max(hi, v);
    }
  }
  return hi > 0.0 ? hi / lo : -1.0;
}

void summary(const Collector& c) {
  std::printf("\n=== MCL stages, ns per item (per-thread CPU time) ===\n");
  std::printf("%7s %4s | %9s %9s %9s %9s | %9s %9s %9s %9s %9s | %9s\n", "N", "K", "bike bat.", "dd batch",
              "bike scal", "dd scalar", "LF batch", "LF scalar", "beam DT", "beam cone", "beam LUT", "resample");
  std::printf("%7s %4s | %9s %9s %9s %9s | %9s %9s %9s %9s %9s | %9s\n", "", "", "/particle", "/particle", "/particle",
              "/particle", "/p-beam", "/p-beam", "/p-beam", "/p-beam", "/p-beam", "/particle");
  for (const std::int64_t k : g_ks)
    for (const std::int64_t n : g_ns) {
      const std::string ns = std::to_string(n), nk = ns + "/" + std::to_string(k);
      std::printf("%7lld %4lld | %9.1f %9.1f %9.1f %9.1f | %9.2f %9.2f %9.1f %9.1f %9.1f | %9.1f\n",
                  static_cast<long long>(n), static_cast<long long>(k), get(c, "BM_predict_bicycle_batch/" + ns),
                  get(c, "BM_predict_diff_drive_batch/" + ns),
                  get(c, "BM_predict_bicycle/" + ns), get(c, "BM_predict_diff_drive/" + ns),
                  get(c, "BM_weight_likelihood_field/" + nk), get(c, "BM_weight_likelihood_field_scalar/" + nk),
                  get(c, "BM_weight_beam/" + nk), get(c, "BM_weight_beam_cone/" + nk),
                  get(c, "BM_weight_beam_table/" + nk), get(c, "BM_resample/" + ns));
    }
  const std::string n_hi = std::to_string(g_ns.back()), k_hi = std::to_string(g_ks.back());
  const std::string steady = n_hi + "/" + k_hi;
  // Each target is judged at its WORST size (the largest per-item cost over every N, and every K for the weights),
  // and the steady-state figure (the largest N and K) is shown beside it.
  const double lf = worst(c, "BM_weight_likelihood_field", true), beam_dt = worst(c, "BM_weight_beam", true);
  const double beam = worst(c, "BM_weight_beam_table", true), cone = worst(c, "BM_weight_beam_cone", true);
  const double bike = worst(c, "BM_predict_bicycle_batch", false), dd = worst(c, "BM_predict_diff_drive_batch", false);
  const double rs = worst(c, "BM_resample", false);
  std::printf("\n=== targets of issue 14 (judged at the worst N, K; steady state N = %s, K = %s in brackets) ===\n",
              n_hi.c_str(), k_hi.c_str());
  std::printf("likelihood field weight <= 1.0 ns/particle-beam : %6.2f (%5.2f)  %s\n", lf,
              get(c, "BM_weight_likelihood_field/" + steady), verdict(lf, 1.0));
  const TableError& e = g_table_error;
  std::printf("beam model weight, exact to one cell, <= 40 ns/particle-beam : %6.1f (%5.1f)  %s  cone caster (%d "
              "headings, %.0f MiB; %.2f %% of rays the exact float, %.2f %% within a cell), readings prepared per "
              "scan, one log per particle\n",
              cone, get(c, "BM_weight_beam_cone/" + steady), verdict(cone, 40.0), kTableBins,
              static_cast<double>(g_cone.bytes_used()) / 1048576.0, 100.0 * e.cone_identical / e.rays,
              100.0 * e.cone_within_cell / e.rays);
  std::printf("  (not exact: the heading lookup table %.1f (%.1f); exact, the distance-transform caster %.1f)\n", beam,
              get(c, "BM_weight_beam_table/" + steady), beam_dt);
  std::printf(
      "motion sampling, bicycle    <= 15 ns/particle   : %6.1f (%5.1f)  %s  batched; per-particle sampler %.1f\n", bike,
      get(c, "BM_predict_bicycle_batch/" + n_hi), verdict(bike, 15.0), get(c, "BM_predict_bicycle/" + n_hi));
  std::printf(
      "motion sampling, diff drive <= 15 ns/particle   : %6.1f (%5.1f)  %s  batched; per-particle sampler %.1f\n", dd,
      get(c, "BM_predict_diff_drive_batch/" + n_hi), verdict(dd, 15.0), get(c, "BM_predict_diff_drive/" + n_hi));
  std::printf("resampling              <= 5 ns/particle        : %6.1f (%5.1f)  %s\n", rs,
              get(c, "BM_resample/" + n_hi), verdict(rs, 5.0));
  std::printf("KLD resampling (no target; a tracking cloud, 500 drawn): %.1f us at N = 256, %.1f us at N = 16384\n"
              "  (table 8.4's count from i.i.d. draws, a binary search each, then the comb over the weighted set)\n",
              get(c, "BM_resample_kld/256") * 256e-3, get(c, "BM_resample_kld/16384") * 16384e-3);
  std::printf(
      "  beam model's table: %.0f MiB, built in %.0f ms; |z*_table - z*_exact| over %d rays to %.0f m from free cells:\n"
      "  mean %.3f m, median %.3f m, p90 %.3f m, p99 %.2f m, max %.2f m; %.1f %% within 0.10 m, %.1f %% within\n"
      "  sigma_hit 0.2 m (the rest are rays passing near a corner, which the table sees hit the other wall)\n",
      static_cast<double>(est::HeadingRangeTableStorage<888, 848, kTableBins>::kBytes) / 1048576.0, g_table_build_ms,
      e.rays, static_cast<double>(kRangeMax), e.mean, e.p50, e.p90, e.p99, e.max, 100.0 * e.within_10cm,
      100.0 * e.within_sigma);
  std::printf("  ray cast alone over the same rays: exact %.0f ns, distance transform %.0f ns, table %.1f ns (atan2 "
              "path), cone %.0f ns (one ray at a time, an atan2 each)\n",
              e.exact_ns, e.dt_ns, e.table_ns, e.cone_ns);
  const double s_lf = spread(c, "BM_weight_likelihood_field", true), s_beam = spread(c, "BM_weight_beam_cone", true);
  const double s_pred = spread(c, "BM_predict_bicycle_batch", false), s_rs = spread(c, "BM_resample", false);
  std::printf("cost linear in N x K (max/min per-item cost over all N, K; <= 1.5 counts as linear):\n");
  std::printf("  likelihood field %.2f %s, beam %.2f %s, predict %.2f %s, resample %.2f %s\n", s_lf,
              s_lf <= 1.5 ? "MET" : "NOT MET", s_beam, s_beam <= 1.5 ? "MET" : "NOT MET", s_pred,
              s_pred <= 1.5 ? "MET" : "NOT MET", s_rs, s_rs <= 1.5 ? "MET" : "NOT MET");
  std::printf("\n=== peers (issue 4: one core, 20 x 20 m map at 5 cm, mean range 6.8 m) ===\n");
  std::printf("stage                               | Beluga 2.1.1 | MRPT 2.5.8 | this build\n");
  std::printf("(this build: worst over N and K)\n");
  std::printf("likelihood field, ns/particle-beam  | ~5           | ~20        | %.2f\n", lf);
  std::printf("beam / ray tracing, ns/particle-beam | ~360         | ~230       | %.1f (exact cone), %.1f (table), "
              "%.1f (exact DT)\n", cone, beam, beam_dt);
  std::printf(
      "motion sampling, ns/particle        | ~128         | ~165       | %.1f (bicycle), %.1f (diff drive)"
      " batched\n",
      bike, dd);
  std::printf("resampling, ns/particle             | 63-116       | 61-66      | %.1f\n", rs);
  std::printf("ray casting alone (RangeLibc): CDDT 27-77 ns per ray, full lookup table 4-19 ns per ray but ~300 MB\n");
}

}  // namespace

int main(int argc, char** argv) {
  if (!parse_arguments(argc, argv)) return 2;
  print_machine();
  setup();
  const est::OccupancyGrid g = g_grid.grid();
  const double cells = static_cast<double>(g.cell_count());
  std::printf("map: %s\n", g_map_name.c_str());
  std::printf(
      "scan: 360 beams (K < 360: every 360/K-th), max range %.0f m, mean range %.2f m, from (%.2f, %.2f); particles:"
      " N(0.3 m, 0.1 rad) around it\n",
      static_cast<double>(kRangeMax), static_cast<double>(g_mean_range), static_cast<double>(g_truth.x),
      static_cast<double>(g_truth.y));
  std::printf("memory of the acceleration structures for this map:\n");
  std::printf("  occupancy grid            1 B/cell: %8.0f KiB\n", cells / 1024.0);
  std::printf(
      "  distance transform        2 B/cell: %8.0f KiB (build %.1f ms; the beam model's ray caster and the"
      " likelihood field share it)\n",
      2.0 * cells / 1024.0, g_edt_build_ms);
  std::printf(
      "  likelihood-field grid     2 B/cell: %8.0f KiB (the map padded by one cell; build %.1f ms from the field's"
      " %d-entry table, %zu B)\n",
      2.0 * (g.width() + 2.0) * (g.height() + 2.0) / 1024.0, g_field_grid_build_ms, g_field.table_entries(),
      sizeof(est::LikelihoodField));
  std::printf("  particle set (N_max = %u) 32 B/particle: %.0f KiB (two buffers of x, y, theta, log w)\n", kNMax,
              static_cast<double>(sizeof(est::ParticleSet<kNMax>)) / 1024.0);
  std::printf("  KLD bin table %zu KiB\n", sizeof(est::BinCounter<4096>) / 1024);
  std::printf("  heading range table  %d x 2 B/cell: %8.0f KiB (build %.0f ms: %d casts from cell centres, distance-"
              "transform caster)\n",
              kTableBins, 2.0 * kTableBins * cells / 1024.0, g_table_build_ms, static_cast<int>(cells) * kTableBins);
  std::printf("  cone caster          %d x 1 B/cell: %8.0f KiB (build %.0f ms; exact)\n", kTableBins,
              static_cast<double>(g_cone.bytes_used()) / 1024.0, g_cone_build_ms);
  Collector collector;
  register_benchmarks();
  benchmark::Initialize(&argc, argv);
  benchmark::RunSpecifiedBenchmarks(&collector);
  summary(collector);
  benchmark::Shutdown();
  return 0;
}
