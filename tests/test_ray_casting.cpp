#include <catch2/catch.hpp>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <string>

#include "datasets.hpp"
#include "est/map/ray_casting.hpp"
#include "est/random/xoshiro128.hpp"
#include "world/office_map.hpp"
#include "maps/ros_map_loader.hpp"

namespace {

est::OccupancyGridStorage<1024, 1024> g_grid;
est::DistanceTransformStorage<1024, 1024> g_edt;

// Reference by dense sampling along the ray (1/512 cell steps): the first sample inside an occupied cell.
// Accurate to 1/512 cell, independent of the traversal logic.
double sampled_range(const est::OccupancyGrid& g, double x, double y, double dx, double dy, double max_range) {
  const double res = g.resolution(), ox = g.origin_x(), oy = g.origin_y();
  const double step = res / 512.0;
  for (double t = 0.0; t < max_range; t += step) {
    const double px = (x + t * dx - ox) / res;
    const double py = (y + t * dy - oy) / res;
    if (px < 0 || py < 0 || px >= g.width() || py >= g.height()) return max_range;
    if (g.is_occupied(static_cast<std::int32_t>(px), static_cast<std::int32_t>(py))) return t;
  }
  return max_range;
}

struct Agreement {
  int rays = 0;
  int differing = 0;
  double max_abs_error = 0.0;
  double exact_seconds = 0.0;
  double fast_seconds = 0.0;
};

// Random rays from random free cells in random directions.
Agreement compare_casters(const est::OccupancyGrid& g, const est::DistanceTransform& dt, int rays, float max_range,
                          std::uint64_t seed) {
  const est::GridRayCaster exact(g);
  const est::DistanceTransformRayCaster fast(g, dt);
  REQUIRE(fast.valid());
  est::Rng rng(seed);
  Agreement a;
  for (int i = 0; i < rays;) {
    const float x = g.origin_x() + rng.uniform(0.0f, static_cast<float>(g.width()) * g.resolution());
    const float y = g.origin_y() + rng.uniform(0.0f, static_cast<float>(g.height()) * g.resolution());
    const float th = rng.uniform(-est::kPi, est::kPi);
    std::int32_t cx = 0, cy = 0;
    if (!g.world_to_cell(x, y, cx, cy) || g.classify(cx, cy) != est::CellClass::free) continue;
    ++i;
    const float dx = std::cos(th), dy = std::sin(th);
    const auto t0 = std::chrono::steady_clock::now();
    const float r_exact = exact.cast(x, y, dx, dy, max_range);
    const auto t1 = std::chrono::steady_clock::now();
    const float r_fast = fast.cast(x, y, dx, dy, max_range);
    const auto t2 = std::chrono::steady_clock::now();
    a.exact_seconds += std::chrono::duration<double>(t1 - t0).count();
    a.fast_seconds += std::chrono::duration<double>(t2 - t1).count();
    ++a.rays;
    const double e = std::fabs(double(r_exact) - double(r_fast));
    if (e > 0.0) ++a.differing;
    if (e > a.max_abs_error) a.max_abs_error = e;
  }
  return a;
}

void print(const char* name, const Agreement& a) {
  std::printf("ray casting on %s: %d rays, %d differ, max |fast - exact| = %.3g m (timing with clock overhead: "
              "exact %.0f ns/ray, accelerated %.0f ns/ray)\n",
              name, a.rays, a.differing, a.max_abs_error, 1e9 * a.exact_seconds / a.rays,
              1e9 * a.fast_seconds / a.rays);
}

void corridor(float resolution) {
  // 40 x 20 cells, a wall column at cx = 30 and a wall row at cy = 15; the rest free.
  REQUIRE(g_grid.configure(40, 20, resolution, -1.0f, -0.5f, est::kFreeCell) == est::MapStatus::ok);
  g_grid.fill_rect(30, 0, 30, 19, est::kOccupiedCell);
  g_grid.fill_rect(0, 15, 39, 15, est::kOccupiedCell);
  g_grid.set(5, 5, est::kUnknownCell);
  REQUIRE(g_edt.build(g_grid.grid()) == est::MapStatus::ok);
}

}  // namespace

// Stated error of the accelerated caster against the exact traversal: zero on every ray tested, bit for bit
// (the header explains why); the assertion allows 1e-4 m for float rounding at exact cell corners.
constexpr double kAcceleratedMaxError = 1e-4;

TEST_CASE("exact traversal returns the distance to the first occupied cell boundary", "[ray_casting]") {
  corridor(0.1f);
  const est::OccupancyGrid g = g_grid.grid();
  const est::GridRayCaster exact(g);
  const est::DistanceTransformRayCaster fast(g, g_edt.view());
  // Start at the centre of cell (10, 5): world (0.05, 0.05). Wall column starts at x = -1 + 3.0 = 2.0.
  for (const auto* name : {"exact", "fast"}) {
    INFO(name);
    auto cast = [&](float x, float y, float dx, float dy, float r) {
      return std::string(name) == "exact" ? exact.cast(x, y, dx, dy, r) : fast.cast(x, y, dx, dy, r);
    };
    CHECK(cast(0.05f, 0.05f, 1.0f, 0.0f, 10.0f) == Approx(1.95f).margin(1e-5));
    CHECK(cast(0.05f, 0.05f, 0.0f, 1.0f, 10.0f) == Approx(0.95f).margin(1e-5));  // row 15 starts at y = 1.0
    const float s = std::sqrt(0.5f);
    CHECK(cast(0.05f, 0.05f, s, s, 10.0f) == Approx(0.95f * std::sqrt(2.0f)).margin(1e-5));
    CHECK(cast(0.05f, 0.05f, -1.0f, 0.0f, 10.0f) == 10.0f);     // leaves the map: max range
    CHECK(cast(0.05f, 0.05f, 0.0f, -1.0f, 0.3f) == 0.3f);       // capped at max range
    CHECK(cast(0.05f, 0.05f, 1.0f, 0.0f, 1.95f) == 1.95f);      // exactly at max range
    CHECK(cast(2.05f, 0.05f, 1.0f, 0.0f, 10.0f) == 0.0f);       // starts inside the wall
    CHECK(cast(-5.0f, 0.05f, 1.0f, 0.0f, 10.0f) == 0.0f);       // starts off the map
    CHECK(cast(__builtin_nanf(""), 0.05f, 1.0f, 0.0f, 10.0f) == 0.0f);
    CHECK(cast(0.05f, 0.05f, __builtin_nanf(""), 0.0f, 10.0f) == 0.0f);
    CHECK(cast(0.05f, 0.05f, 1.0f, 0.0f, __builtin_nanf("")) == 0.0f);
    CHECK(cast(0.05f, 0.05f, 1.0f, 0.0f, -1.0f) == 0.0f);
    CHECK(cast(0.05f, 0.05f, 1.0f, 0.0f, __builtin_inff()) == Approx(1.95f).margin(1e-5));
    CHECK(cast(-0.45f, 0.05f, 0.0f, 1.0f, 10.0f) == Approx(0.95f).margin(1e-5));  // through the unknown cell
  }
}

TEST_CASE("exact traversal agrees with dense sampling along random rays", "[ray_casting]") {
  est::sim::make_office_map(g_grid);
  const est::OccupancyGrid g = g_grid.grid();
  const est::GridRayCaster exact(g);
  est::Rng rng(5u);
  double worst = 0.0;
  for (int i = 0; i < 300;) {
    const float x = rng.uniform(0.2f, 19.8f), y = rng.uniform(0.2f, 14.8f), th = rng.uniform(-est::kPi, est::kPi);
    std::int32_t cx = 0, cy = 0;
    if (!g.world_to_cell(x, y, cx, cy) || g.is_occupied(cx, cy)) continue;
    ++i;
    const float dx = std::cos(th), dy = std::sin(th);
    const double e = std::fabs(double(exact.cast(x, y, dx, dy, 8.0f)) - sampled_range(g, x, y, dx, dy, 8.0));
    if (e > worst) worst = e;
  }
  // The sampled reference is late by at most one sample (1/512 cell) plus float rounding of the start point.
  CHECK(worst < double(g.resolution()) / 512.0 + 1e-5);
}

TEST_CASE("accelerated ray casting equals the exact traversal on the synthetic office", "[ray_casting]") {
  est::sim::make_office_map(g_grid);
  REQUIRE(g_edt.build(g_grid.grid()) == est::MapStatus::ok);
  const Agreement a = compare_casters(g_grid.grid(), g_edt.view(), 20000, 30.0f, 11u);
  print("synthetic office (400 x 300, 30 m)", a);
  CHECK(a.max_abs_error <= kAcceleratedMaxError);
  const Agreement b = compare_casters(g_grid.grid(), g_edt.view(), 5000, 2.0f, 12u);
  print("synthetic office (400 x 300, 2 m)", b);
  CHECK(b.max_abs_error <= kAcceleratedMaxError);
}

TEST_CASE("accelerated ray casting equals the exact traversal on the Intel map", "[ray_casting][dataset]") {
  const std::string dir = test_support::dataset_or_skip("carmen-radish-logs") + "/..";
  const std::string path = dir + "/carmen-radish-logs/occupancy-maps-gondsm/intel.pgm";
  est::sim::load_trinary_pgm_map(path, g_grid);
  REQUIRE(g_grid.width() == 888);
  const auto t0 = std::chrono::steady_clock::now();
  REQUIRE(g_edt.build(g_grid.grid()) == est::MapStatus::ok);
  const double build_ms = 1e3 * std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::printf("distance transform of the Intel map (888 x 848): %.1f ms, %u bytes in the 1024 x 1024 storage\n",
              build_ms, est::DistanceTransformStorage<1024, 1024>::kBytes);
  const Agreement a = compare_casters(g_grid.grid(), g_edt.view(), 20000, 30.0f, 13u);
  print("Intel map (888 x 848 at 0.05 m, 30 m)", a);
  CHECK(a.max_abs_error <= kAcceleratedMaxError);
}

TEST_CASE("ray casts are bit-identical run to run", "[ray_casting]") {
  est::sim::make_office_map(g_grid);
  REQUIRE(g_edt.build(g_grid.grid()) == est::MapStatus::ok);
  const est::DistanceTransformRayCaster fast(g_grid.grid(), g_edt.view());
  const float r1 = fast.cast(3.3f, 7.1f, 0.6f, 0.8f, 20.0f);
  const float r2 = fast.cast(3.3f, 7.1f, 0.6f, 0.8f, 20.0f);
  CHECK(r1 == r2);
}

// The walks of the accelerated casters end at min(max_range, t_exit()) and check no cell against the map: that is
// exact only if a step's t reaches t_exit() exactly when it leaves the map (the same float) and stays below it on the
// map, and if a jump below t_exit() lands on the map (land_inside()).
TEST_CASE("a walk leaves the map exactly at t_exit(), and a landing below it is on the map", "[ray_casting]") {
  REQUIRE(g_grid.configure(37, 23, 0.1f, -1.0f, -0.5f, est::kFreeCell) == est::MapStatus::ok);
  const est::OccupancyGrid& g = g_grid.grid();
  const std::int32_t w = g.width(), h = g.height();
  est::Rng rng(21u);
  int rays = 0, steps = 0, landings = 0, near_edge = 0;
  for (int i = 0; i < 20000; ++i) {
    // Starts anywhere, a fifth of them on a cell boundary or the map's edge; headings anywhere, a fifth along an axis
    // or a diagonal.
    float gx = rng.uniform(0.0f, static_cast<float>(w)), gy = rng.uniform(0.0f, static_cast<float>(h));
    if (i % 5 == 1) gx = static_cast<float>(static_cast<std::int32_t>(gx));
    if (i % 5 == 2) gy = 0.0f;
    float th = rng.uniform(-est::kPi, est::kPi);
    if (i % 5 == 3) th = static_cast<float>(static_cast<std::int32_t>(rng.uniform(0.0f, 8.0f))) * (est::kPi / 4.0f);
    const float dx = i % 5 == 3 && std::fabs(std::cos(th)) < 1e-6f ? 0.0f : std::cos(th);
    const float dy = i % 5 == 3 && std::fabs(std::sin(th)) < 1e-6f ? 0.0f : std::sin(th);
    est::detail::GridRay r{};
    if (!r.init(g, g.origin_x() + gx * g.resolution(), g.origin_y() + gy * g.resolution(), dx, dy, 1e6f)) continue;
    ++rays;
    // 0 (or -0) for a start on the edge it heads out of.
    const float t_exit = r.t_exit(w, h);
    REQUIRE(t_exit >= 0.0f);
    REQUIRE(t_exit < est::detail::GridRay::kNever);
    // Landings at random t below t_exit() are on the map, in the cell of the point (but within rounding of a cell's
    // boundary).
    for (int k = 0; k < 4 && t_exit > 0.0f; ++k) {
      est::detail::GridRay l = r;
      const float t = k == 0 ? std::nextafter(t_exit, 0.0f) : rng.uniform(0.0f, t_exit);
      l.land_inside(t, w, h);
      ++landings;
      CHECK(g.contains(l.ix, l.iy));
      const double px = double(r.gx) + double(t) * double(r.dx), py = double(r.gy) + double(t) * double(r.dy);
      const bool on_boundary = std::fabs(px - std::round(px)) < 1e-4 || std::fabs(py - std::round(py)) < 1e-4;
      if (on_boundary) {
        ++near_edge;
      } else {
        CHECK(l.ix == static_cast<std::int32_t>(px));
        CHECK(l.iy == static_cast<std::int32_t>(py));
      }
    }
    // Steps: below t_exit() on the map, and the step that leaves the map has t == t_exit(), bit for bit.
    for (int n = 0; n < w + h + 4; ++n) {
      const float t = r.step();
      ++steps;
      if (g.contains(r.ix, r.iy)) {
        CHECK(t < t_exit);
        if (!(t < t_exit)) break;
      } else {
        CHECK(std::memcmp(&t, &t_exit, sizeof t) == 0);
        break;
      }
    }
  }
  std::printf("t_exit: %d rays, %d steps, %d landings (%d within 1e-4 cell of a boundary)\n", rays, steps, landings,
              near_edge);
  CHECK(rays > 19000);
}
