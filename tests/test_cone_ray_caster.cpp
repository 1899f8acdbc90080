#include <catch2/catch.hpp>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <initializer_list>
#include <string>
#include <vector>

#include "caster_agreement.hpp"
#include "datasets.hpp"
#include "est/filter/augmented_mcl.hpp"
#include "est/loop/beam_scan.hpp"
#include "est/map/cone_ray_caster.hpp"
#include "est/map/ray_casting.hpp"
#include "est/random/xoshiro128.hpp"
#include "est/sensor/beam_range_finder_model_cone.hpp"
#include "est/sensor/beam_readings.hpp"
#include "est/sensor/range_scan.hpp"
#include "world/office_map.hpp"
#include "maps/ros_map_loader.hpp"

namespace {

using test_support::Agreement;

est::OccupancyGridStorage<1024, 1024> g_grid;
// Enough for the Intel map (888 x 848) at 64 headings (bench_sensor_models prints the figures): 48 MB.
est::ConeRayCasterStorage<64, 888, 848> g_cone;

void print(const char* name, const Agreement& s, double build_ms) {
  std::printf("cone ray caster on %s: build %.0f ms, %.1f MiB; %d rays: %d identical to the exact traversal "
              "(%.3f %%), %.3f %% within one cell, worst |error| %.3f m\n",
              name, build_ms, g_cone.bytes_used() / 1048576.0, s.rays, s.identical, 100.0 * s.identical / s.rays,
              100.0 * s.within_cell / s.rays, s.worst);
}

double build(int bins);

// Random rays on the map in g_grid at `bins` headings and two max ranges: >= 99.9 % identical and within a cell.
void check_agreement(const char* map, int bins, std::initializer_list<float> ranges, std::uint64_t seed) {
  const double ms = build(bins);
  for (float range : ranges) {
    const Agreement s = test_support::random_rays(g_grid.grid(), g_cone.view(), 20000, range, seed);
    char name[128];
    std::snprintf(name, sizeof name, "%s, %d headings, %.0f m", map, bins, static_cast<double>(range));
    print(name, s, ms);
    CHECK(s.within_cell >= s.rays * 999 / 1000);
    CHECK(s.identical >= s.rays * 999 / 1000);
  }
}

double build(int bins) {
  const auto t0 = std::chrono::steady_clock::now();
  REQUIRE(g_cone.build(g_grid.grid(), bins) == est::ConeRayCasterStatus::ok);
  return 1e3 * std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// The table's claim itself: from a random point of a free cell, at a random heading within 1.2 bins' halves of bin
// b (what the query trusts), the exact traversal enters no occupied cell before bound_cells(b, cell). Returns the
// rays that beat their bound (0 when the claim holds) and prints how tight the bounds are.
template <class Cone>
int rays_beating_the_bound(const est::OccupancyGrid& g, const Cone& cone, int rays, std::uint64_t seed) {
  const est::GridRayCaster exact(g);
  est::Rng rng(seed);
  const float half = est::kPi / static_cast<float>(cone.bins());
  const float far = static_cast<float>(g.width() + g.height()) * g.resolution() * 2.0f;
  int n = 0, beaten = 0;
  double slack = 0.0;
  while (n < rays) {
    const std::int32_t cx = static_cast<std::int32_t>(rng.uniform(0.0f, static_cast<float>(g.width())));
    const std::int32_t cy = static_cast<std::int32_t>(rng.uniform(0.0f, static_cast<float>(g.height())));
    if (!g.contains(cx, cy) || g.is_occupied_value(g.at(cx, cy))) continue;
    const std::int32_t b = static_cast<std::int32_t>(rng.uniform(0.0f, static_cast<float>(cone.bins()))) % cone.bins();
    const float th = 2.0f * half * static_cast<float>(b) + rng.uniform(-1.2f, 1.2f) * half;
    const float x = g.origin_x() + (static_cast<float>(cx) + rng.uniform(0.0f, 1.0f)) * g.resolution();
    const float y = g.origin_y() + (static_cast<float>(cy) + rng.uniform(0.0f, 1.0f)) * g.resolution();
    std::int32_t sx = 0, sy = 0;
    if (!g.world_to_cell(x, y, sx, sy) || sx != cx || sy != cy) continue;  // rounded onto a neighbour
    ++n;
    const float r = exact.cast(x, y, std::cos(th), std::sin(th), far);
    const std::int32_t bound = cone.bound_cells(b, cx, cy);
    if (r >= far) continue;  // leaves the map: any bound holds
    const double hit = static_cast<double>(r / g.resolution());
    beaten += hit < static_cast<double>(bound) ? 1 : 0;
    slack += hit - static_cast<double>(bound);
  }
  std::printf("cone ray caster, %d headings: %d of %d rays beat their bound; the bound is %.1f cells short of the "
              "hit on average\n", cone.bins(), beaten, rays, slack / rays);
  return beaten;
}

// The beam model's set-up of the tests below: the model, a 360-beam scan cast exactly from `truth` on g_grid, its
// bearings in `bins` headings and its readings, prepared (the views point into static storage).
struct BeamSetup {
  est::BeamRangeFinderModel model = test_support::beam_model(20.0f);
  est::Pose2 truth{5.5f, 7.3f, 0.3f};
  est::ScanBeams z{};
  est::BeamBearings bearings{};
  est::BeamReadings readings{};
};
BeamSetup prepare_beams(std::int32_t bins) {
  static est::PreparedScan<360> scan;
  static est::BeamBearingsStorage<360> bearings;
  static est::BeamReadingsStorage<360> readings;
  BeamSetup s;
  REQUIRE(s.model.ready());
  REQUIRE(test_support::prepare_exact_scan(g_grid.grid(), s.truth, 20.0f, scan));
  s.z = scan.beams();
  REQUIRE(bearings.prepare(s.z, bins));
  REQUIRE(readings.prepare(s.z, s.model));
  s.bearings = bearings.view();
  s.readings = readings.view();
  return s;
}

// A pose drawn uniformly within +-xy and +-th of p.
est::Pose2 around(const est::Pose2& p, est::Rng& rng, float xy, float th) {
  return {p.x + rng.uniform(-xy, xy), p.y + rng.uniform(-xy, xy), p.theta + rng.uniform(-th, th)};
}

}  // namespace

TEST_CASE("cone caster keeps the exact caster's conventions", "[cone_ray_caster]") {
  // 40 x 20 cells of 0.1 m, a wall column at cx = 30; open to the left and up.
  REQUIRE(g_grid.configure(40, 20, 0.1f, 0.0f, 0.0f, est::kFreeCell) == est::MapStatus::ok);
  g_grid.fill_rect(30, 0, 30, 19, est::kOccupiedCell);
  build(16);
  const est::ConeRayCaster c = g_cone.view();
  REQUIRE(c.valid());
  CHECK(c.cast(0.55f, 1.05f, 1.0f, 0.0f, 10.0f) == Approx(2.45f).margin(1e-5f));
  CHECK(c.cast(0.52f, 1.05f, 1.0f, 0.0f, 10.0f) == Approx(2.48f).margin(1e-5f));
  CHECK(c.cast(3.05f, 1.05f, 1.0f, 0.0f, 10.0f) == 0.0f);     // start in an occupied cell
  CHECK(c.cast(-0.1f, 1.05f, 1.0f, 0.0f, 10.0f) == 0.0f);     // start off the map
  CHECK(c.cast(NAN, 1.05f, 1.0f, 0.0f, 10.0f) == 0.0f);       // non-finite start
  CHECK(c.cast(0.55f, 1.05f, NAN, 0.0f, 10.0f) == 0.0f);      // non-finite direction
  CHECK(c.cast(0.55f, 1.05f, 2.0f, 0.0f, 10.0f) == 0.0f);     // not a unit vector
  CHECK(c.cast(0.55f, 1.05f, -1.0f, 0.0f, 10.0f) == 10.0f);   // leaves the map: no hit
  CHECK(c.cast(0.55f, 1.05f, 1.0f, 0.0f, 1.0f) == 1.0f);      // capped at max range
  CHECK(c.cast(0.55f, 1.05f, 1.0f, 0.0f, 0.0f) == 0.0f);      // max range <= 0
  CHECK(c.cast(0.55f, 1.05f, 0.0f, 1.0f, 10.0f) == 10.0f);    // along the wall, never reaching it
  // A heading given far from the ray's is replaced by the ray's own: still exact (the bound is for the cone of
  // the bin it is read from, so trusting a wrong bin could jump through the wall).
  const est::ConeRayCaster::Origin o = c.origin(0.55f, 1.05f);
  CHECK(c.cast_from(o, 1.0f, 0.0f, 5.0f, 10.0f) == Approx(2.45f).margin(1e-5f));
  CHECK(c.cast_from(o, 1.0f, 0.0f, NAN, 10.0f) == Approx(2.45f).margin(1e-5f));
  CHECK(c.cast_from(o, 1.0f, 0.0f, 3e9f, 10.0f) == Approx(2.45f).margin(1e-5f));
  // The bounds: the wall's cells 0; a cell facing it at 2.5 cells no more than the run to it.
  CHECK(c.bound_cells(0, 30, 5) == -1);
  CHECK(c.bound_cells(0, 27, 5) >= 0);
  CHECK(c.bound_cells(0, 27, 5) <= 2);
  CHECK(c.bound_cells(16, 27, 5) == -1);  // off the table
  CHECK(c.bound_cells(0, 40, 5) == -1);
}

TEST_CASE("cone caster rejects bad builds with a reason", "[cone_ray_caster]") {
  est::sim::make_office_map(g_grid);
  CHECK(g_cone.build(g_grid.grid(), 48) == est::ConeRayCasterStatus::bad_bins);
  CHECK(g_cone.build(g_grid.grid(), 4) == est::ConeRayCasterStatus::bad_bins);
  CHECK(g_cone.build(g_grid.grid(), 128) == est::ConeRayCasterStatus::bad_bins);  // above the storage's T
  CHECK(!g_cone.view().valid());
  CHECK(g_cone.build(est::OccupancyGrid{}, 16) == est::ConeRayCasterStatus::bad_grid);
  static est::ConeRayCasterStorage<16, 100, 100> small;  // smaller than the office
  CHECK(small.build(g_grid.grid(), 16) == est::ConeRayCasterStatus::bad_grid);
  CHECK(!small.view().valid());
}

// The claim the jumps rest on: no ray beats its cell's bound (a broken bound shows here first, before it shows as a
// wrong range).
TEST_CASE("cone caster's bounds hold for every ray of their cone", "[cone_ray_caster]") {
  est::sim::make_office_map(g_grid);
  for (int bins : {8, 16, 64}) {
    build(bins);
    CHECK(rays_beating_the_bound(g_grid.grid(), g_cone.view(), 20000, 5u + static_cast<unsigned>(bins)) == 0);
  }
}

// The accuracy claim: >= 99.9 % of rays within one cell of the exact traversal (measured: every ray identical).
TEST_CASE("cone caster agrees with the exact traversal on the synthetic office", "[cone_ray_caster]") {
  est::sim::make_office_map(g_grid);
  for (int bins : {8, 16, 64})
    check_agreement("the synthetic office (400 x 300 at 0.05 m)", bins, {2.0f, 20.0f},
                    7u + static_cast<unsigned>(bins));
}

TEST_CASE("cone caster agrees with the exact traversal at cell centres and along the axes", "[cone_ray_caster]") {
  est::sim::make_office_map(g_grid);
  build(64);
  const Agreement s = test_support::centre_rays(g_grid.grid(), g_cone.view(), 20.0f);
  std::printf("cone ray caster, %d rays from cell centres at multiples of 45 deg: %d identical, worst %.3f m\n",
              s.rays, s.identical, s.worst);
  CHECK(s.identical >= s.rays * 999 / 1000);
  CHECK(s.worst <= 0.05 + 1e-6);
}

TEST_CASE("cone caster walks a ray grazing a wall to its end", "[cone_ray_caster]") {
  // A corridor 600 cells long, the ray half a cell from its wall and at a slight angle to it: every bound is under
  // a cell, so the cast is steps of the traversal all the way (the loop's bound, 3 (W + H) + 8, is what ends it).
  REQUIRE(g_grid.configure(600, 6, 0.05f, 0.0f, 0.0f, est::kFreeCell) == est::MapStatus::ok);
  g_grid.fill_rect(0, 0, 599, 0, est::kOccupiedCell);
  g_grid.fill_rect(599, 0, 599, 5, est::kOccupiedCell);
  build(64);
  const est::GridRayCaster exact(g_grid.grid());
  const est::ConeRayCaster cone = g_cone.view();
  for (float a : {0.0f, 0.0005f, -0.0005f, 0.001f}) {
    const float dx = std::cos(a), dy = std::sin(a);
    const float e = exact.cast(0.02f, 0.075f, dx, dy, 40.0f), c = cone.cast(0.02f, 0.075f, dx, dy, 40.0f);
    CHECK(std::memcmp(&e, &c, sizeof(float)) == 0);
  }
}

TEST_CASE("cone caster agrees with the exact traversal on the Intel map", "[cone_ray_caster][dataset]") {
  const std::string dir = test_support::dataset_or_skip("carmen-radish-logs") + "/..";
  est::sim::load_trinary_pgm_map(dir + "/carmen-radish-logs/occupancy-maps-gondsm/intel.pgm", g_grid);
  REQUIRE(g_grid.width() == 888);
  for (int bins : {32, 64}) {
    check_agreement("the Intel map (888 x 848 at 0.05 m)", bins, {5.0f, 30.0f}, 13u + static_cast<unsigned>(bins));
    CHECK(rays_beating_the_bound(g_grid.grid(), g_cone.view(), 20000, 3u + static_cast<unsigned>(bins)) == 0);
  }
}

TEST_CASE("beam model on the cone caster gives the exact caster's densities, their product in log space",
          "[cone_ray_caster]") {
  est::sim::make_office_map(g_grid);
  build(64);
  const est::ConeRayCaster cone = g_cone.view();
  const est::GridRayCaster exact(g_grid.grid());
  const BeamSetup beams = prepare_beams(cone.bins());
  const est::BeamRangeFinderModel& model = beams.model;
  const est::Pose2 truth = beams.truth;
  const est::ScanBeams z = beams.z;
  est::Rng rng(21u);
  double worst = 0.0;
  for (int i = 0; i < 200; ++i) {
    const est::Pose2 x = around(truth, rng, 0.3f, 0.1f);
    // The exact caster's per-beam log densities, summed in double: the reference of LogProduct's bound.
    const est::SensorFrame f = est::sensor_frame(x, {});
    double ref = 0.0;
    for (std::int32_t k = 0; k < z.count; ++k) {
      const float dx = f.c * z.ux[k] - f.s * z.uy[k], dy = f.s * z.ux[k] + f.c * z.uy[k];
      const float e = exact.cast(f.x, f.y, dx, dy, 20.0f);
      const float c = cone.cast(f.x, f.y, dx, dy, 20.0f);
      REQUIRE(std::memcmp(&e, &c, sizeof(float)) == 0);  // the same z* on every beam
      ref += static_cast<double>(model.log_density(z.is_max[k] ? 20.0f : z.range[k], e));
    }
    const float fast = est::beam_range_finder_model(z, beams.bearings, beams.readings, x, {}, cone, model);
    const float again = est::beam_range_finder_model(z, beams.bearings, beams.readings, x, {}, cone, model);
    REQUIRE(std::memcmp(&fast, &again, sizeof(float)) == 0);
    const double bound = z.count * std::ldexp(1.0, -24) + 4.0 * std::fabs(ref) * std::ldexp(1.0, -23);
    CHECK(std::fabs(double(fast) - ref) <= bound);
    worst = std::max(worst, std::fabs(double(fast) - ref));
  }
  std::printf("beam model on the cone caster: worst |log q - sum of exact log densities| %.2e nats over 200 "
              "particles, 360 beams\n", worst);
  // Bearings prepared for another heading count, or a caster not built, are refused.
  static est::BeamBearingsStorage<360> wrong;
  REQUIRE(wrong.prepare(z, 32));
  CHECK(est::beam_range_finder_model(z, wrong.view(), beams.readings, truth, {}, cone, model) ==
        360.0f * est::kBeamLogDensityFloor);
  CHECK(est::beam_range_finder_model(z, beams.bearings, beams.readings, truth, {}, est::ConeRayCaster{}, model) ==
        360.0f * est::kBeamLogDensityFloor);
}

// The packed table (4 bits per cell and heading, kConeLevels): half the memory, every bound the largest level not
// above the byte table's, so the bounds still hold and the ranges stay the exact traversal's.
TEST_CASE("cone caster packed in 4 bits: half the memory, bounds rounded down to a level, the same ranges",
          "[cone_ray_caster]") {
  static est::ConeRayCasterStorage<64, 400, 300, 4> packed;
  est::sim::make_office_map(g_grid);
  for (int bins : {16, 64}) {
    build(bins);
    REQUIRE(packed.build(g_grid.grid(), bins) == est::ConeRayCasterStatus::ok);
    const est::ConeRayCaster bytes = g_cone.view();
    const est::PackedConeRayCaster nibbles = packed.view();
    CHECK_FALSE(g_cone.packed_view().valid());  // each table has the view of its own kind only
    CHECK_FALSE(packed.ConeRayCasterBuffer::view().valid());
    const std::uint32_t cells = 400u * 300u, ubins = static_cast<std::uint32_t>(bins);
    CHECK(packed.bytes_used() == ubins / 2u * cells + 8u * ubins);
    CHECK(g_cone.bytes_used() == ubins * cells + 8u * ubins);
    // Every entry: the largest level not above the byte table's (the bound is e - 1 cells).
    int wrong = 0;
    for (std::int32_t b = 0; b < bins; ++b)
      for (std::int32_t y = 0; y < 300; ++y)
        for (std::int32_t x = 0; x < 400; ++x) {
          const std::int32_t e = bytes.bound_cells(b, x, y) + 1, p = nibbles.bound_cells(b, x, y) + 1;
          std::int32_t want = 0;
          for (std::uint8_t level : est::kConeLevels)
            if (level <= e) want = level;
          wrong += p == want ? 0 : 1;
        }
    CHECK(wrong == 0);
    CHECK(rays_beating_the_bound(g_grid.grid(), nibbles, 20000, 31u + ubins) == 0);
    for (float range : {2.0f, 20.0f}) {
      const Agreement s = test_support::random_rays(g_grid.grid(), nibbles, 20000, range, 37u + ubins);
      std::printf("packed cone ray caster, %d headings, %.0f m: %.1f MiB; %d of %d rays identical to the exact "
                  "traversal, worst |error| %.3f m\n", bins, static_cast<double>(range),
                  packed.bytes_used() / 1048576.0, s.identical, s.rays, s.worst);
      CHECK(s.identical >= s.rays * 999 / 1000);
      CHECK(s.within_cell >= s.rays * 999 / 1000);
    }
  }
  // The beam model over either table: the same log likelihood, bit for bit, particle after particle (64 headings).
  const est::ConeRayCaster bytes = g_cone.view();
  const est::PackedConeRayCaster nibbles = packed.view();
  const BeamSetup beams = prepare_beams(bytes.bins());
  est::Rng rng(41u);
  int differ = 0;
  for (int i = 0; i < 200; ++i) {
    const est::Pose2 x = around(beams.truth, rng, 0.5f, 0.2f);
    const float a = est::beam_range_finder_model(beams.z, beams.bearings, beams.readings, x, {}, bytes, beams.model);
    const float b =
        est::beam_range_finder_model(beams.z, beams.bearings, beams.readings, x, {}, nibbles, beams.model);
    differ += std::memcmp(&a, &b, sizeof(float)) == 0 ? 0 : 1;
  }
  CHECK(differ == 0);
  // And in MCL's correction (est/loop/beam_scan.hpp): the same weights from either table, and they moved.
  est::MclConfig cfg;
  cfg.recovery = false;
  static est::AugmentedMcl<256> by_bytes(cfg, 9u), by_nibbles(cfg, 9u);
  by_bytes.initialize_gaussian(beams.truth, 0.3f, 0.1f, 256);
  by_nibbles.initialize_gaussian(beams.truth, 0.3f, 0.1f, 256);
  est::loop::BeamConeScan<360> scan_bytes(bytes, beams.model);
  est::loop::BeamConeScan<360, est::PackedConeRayCaster> scan_nibbles(nibbles, beams.model);
  scan_bytes.correct(by_bytes, beams.z, {});
  scan_nibbles.correct(by_nibbles, beams.z, {});
  const est::ConstParticleSetView pa = by_bytes.particles(), pb = by_nibbles.particles();
  REQUIRE(pa.count == pb.count);
  CHECK(std::memcmp(pa.log_w, pb.log_w, sizeof(float) * pa.count) == 0);
  float spread = 0.0f;
  for (std::uint32_t i = 1; i < pa.count; ++i) spread = std::fmax(spread, std::fabs(pa.log_w[i] - pa.log_w[0]));
  CHECK(spread > 1.0f);  // the scan told the particles apart
}

#if defined(__x86_64__)
namespace {
// cast_lanes_from<G>() against cast_from() ray by ray, 8 G rays from each of `origins` random starts (some off the
// map or in walls), at random headings, with some headings given wrong, some directions not unit or not finite, and
// max ranges from none to beyond the map. Returns the rays whose floats differ; counts hits and rays cast.
template <std::uint32_t G, class Cone>
int lanes_mismatches(const Cone& cone, int origins, std::uint64_t seed, int& rays, int& hits) {
  const est::OccupancyGrid g = cone.grid();
  constexpr std::uint32_t n = 8 * G;
  est::Rng rng(seed);
  int bad = 0;
  for (int i = 0; i < origins; ++i) {
    const float x = rng.uniform(-0.5f, static_cast<float>(g.width()) * g.resolution() + 0.5f);
    const float y = rng.uniform(-0.5f, static_cast<float>(g.height()) * g.resolution() + 0.5f);
    const typename Cone::Origin o = cone.origin(x, y);
    const float ranges[] = {0.0f, 0.3f, 2.0f, 20.0f, 1e6f};
    const float max_range = ranges[i % 5];
    float dx[n], dy[n], hb[n], out[n];
    const float th0 = rng.uniform(-est::kPi, est::kPi);
    for (std::uint32_t j = 0; j < n; ++j) {
      const float th = (i % 3 == 0) ? rng.uniform(-est::kPi, est::kPi) : th0 + 0.02f * static_cast<float>(j);
      dx[j] = std::cos(th);
      dy[j] = std::sin(th);
      hb[j] = th * cone.bins_per_rad() + (j % 7 == 3 ? 2.0f : 0.0f);  // a heading 2 bins off: the ray's is taken
      if (i % 11 == 5 && j == 1) dx[j] = 2.0f;                       // not a unit vector
      if (i % 13 == 6 && j == 2) dy[j] = NAN;
      if (i % 17 == 7 && j == 0) dx[j] = 0.0f, dy[j] = 1.0f;  // along a grid line
    }
    cone.template cast_lanes_from<G>(o, dx, dy, hb, max_range, out);
    for (std::uint32_t j = 0; j < n; ++j) {
      const float want = cone.cast_from(o, dx[j], dy[j], hb[j], max_range);
      bad += std::memcmp(&want, &out[j], sizeof(float)) == 0 ? 0 : 1;
      hits += want > 0.0f && want < max_range ? 1 : 0;
      ++rays;
    }
  }
  return bad;
}
}  // namespace

TEST_CASE("cone caster walks 8 or 32 rays in AVX2 lanes with each ray's own float", "[cone_ray_caster]") {
  if (!est::ConeRayCaster::lanes_vectorized()) {
    std::fprintf(stderr, "SKIP: this CPU has no AVX2: cast_lanes_from() casts one ray at a time\n");
    std::fflush(stderr);
    std::_Exit(77);
  }
  static est::ConeRayCasterStorage<64, 400, 300, 4> packed;
  est::sim::make_office_map(g_grid);
  for (int bins : {16, 64}) {
    build(bins);
    REQUIRE(packed.build(g_grid.grid(), bins) == est::ConeRayCasterStatus::ok);
    int rays = 0, hits = 0;
    CHECK(lanes_mismatches<1>(g_cone.view(), 3000, 41u, rays, hits) == 0);
    CHECK(lanes_mismatches<4>(g_cone.view(), 2000, 43u, rays, hits) == 0);
    CHECK(lanes_mismatches<4>(packed.view(), 2000, 47u, rays, hits) == 0);
    std::printf("cone caster lanes, %d headings: %d rays, %d hits, each the float of cast_from()\n", bins, rays,
                hits);
    CHECK(hits > rays / 4);
  }
}
#endif
