#pragma once
// Exact ray casting by a directional distance table, for the beam model's z* (Thrun table 6.1, line 3): the answer
// of GridRayCaster (ray_casting.hpp), found by a few jumps instead of a walk.
//
// A directional distance transform (RangeLibc's DDT, Walsh and Karaman 2018) stores for each of T headings and each
// cell the distance to the first obstacle along that heading; read at a ray's own position and heading it would be
// approximate (the heading is quantized, the cell is wider than a ray). Here each entry is instead a distance that
// no ray can beat: for heading bin b and cell c, a lower bound on the path from any point of c's square, at any
// heading within 1.25 bins' halves of b (a cone), to the first occupied cell it enters. A ray of that bin jumps by
// it without passing an obstacle, reads the entry of the cell it lands in, and so on; where the bound is under one
// cell it takes one exact step of the traversal instead. The traversal's crossings are computed from the cell index
// and the ray's start (GridRay::step()), as after a jump of DistanceTransformRayCaster, so the range returned is
// GridRayCaster's float, except where a jump lands within rounding of a cell corner.
// On an x86-64 host with AVX2, cast_lanes_from() walks 8 G rays from one start at once (the beam model: 64), eight
// to a register, each lane taking its jump or its step by blends: the same floats as cast_from() (tested; the
// self-test's digest is the boards'), with the table reads of many rays in flight instead of one ray's chain of
// them; without AVX2 it casts one ray at a time. (A jump in fixed point, 2^-14 cell, shortened one ray's chain on
// the host, 56-59 against 86 ns per particle-beam, but costs two 32 x 32-bit high products per move in lanes and
// saved 2 % on the board: the jumps land in floats, as GridRay::land_inside().)
//
// The bound, for a bin whose headings all have cos > 0 (x-dominant, the other three cases by symmetry): a ray from
// (x0, y0) in [cx, cx + 1] x [cy, cy + 1] reaches column cx + i after a horizontal run of at least i - 1 cells, so
// its path is at least (i - 1) / max|cos| over the cone; within column cx + i its run is in [max(0, i - 1), i + 1],
// so its y lies in [cy + run m_lo, cy + 1 + run m_hi] (m the slope over the cone): a fixed range of rows relative
// to cy. The entry is the smallest bound over the first k + 1 columns (k = kDirect = 16) whose rows hold an
// occupied cell (a prefix count per column), and beyond them k / max|cos| plus the smallest entry of the cells in
// column cx + k + 1 the cone enters it through (the same bound, from their squares). Stored per cell as one byte:
// 0 occupied, 1 a free cell whose bound is under one cell (take a step), e >= 2 a jump of e - 1 cells less 1/64
// (float rounding); 255 also for bounds of 254 cells or more and for cones that leave the map without an obstacle.
//
// Conventions are GridRayCaster's: unknown cells are free; a start in an occupied cell, outside the map or
// non-finite returns 0; no hit before max_range or the map's edge returns max_range. A direction must be a unit
// vector: one with a component beyond 1.5 returns 0, like a non-finite one.
// Memory: T bytes per cell (Intel map 888 x 848 at T = 64: 46 MiB; the board's room 160 x 120 at T = 16: 307 KB),
// or T / 2 packed (ConeRayCasterStorage<T, W, H, 4>, PackedConeRayCaster: a 4-bit code per entry, the largest of 16
// levels not above it, kConeLevels; the same ranges, a few more jumps: 154 KB for the room, 312 KiB for a 200 x 200
// map at T = 16), plus 8 bytes per heading; the build's scratch: two prefix counts (2 bytes per cell each), a byte
// per cell and a line of floats.
// Cost (Intel map, T = 64, host, the beam model through cast_lanes_from() and lane densities): ~22 ns per
// particle-beam in bench_sensor_models (2.3 jumps and 2.3 exact steps per cast), 30-34 in bench_mcl's workload (4.0
// jumps and 2.7 steps: longer rays); on the M4F at T = 16 see the README's board table (bench_mcl; 467 instructions
// per particle-beam, 508 packed). Every loop is bounded: a jump advances the ray by at least 63/64 cell and a step
// moves it one cell, so a cast ends within 3 (W + H) + 8 iterations; the accuracy is tested against GridRayCaster
// (tests/test_cone_ray_caster.cpp).
// Build: per heading, kDirect + 1 prefix-count reads and a window of bounds per cell, in loops over whole lines;
// ~0.45 s for the Intel map at T = 64 on the host, meant for start-up or the host.
#include <cstdint>

#include "est/map/occupancy_grid.hpp"
#include "est/map/ray_casting.hpp"
#include "est/math/fmath.hpp"
#if defined(__x86_64__)
#include <immintrin.h>
#endif

namespace est {

// The packed table's 16 codes (4 bits per cell and heading): code c stands for the entry kConeLevels[c], the largest
// level not above the bound's entry, so a packed bound is never longer than the byte it replaces. 0 and 1 keep their
// meaning (occupied, take a step); the jumps are 1-212 cells in steps of ~1.45.
inline constexpr std::uint8_t kConeLevels[16] = {0, 1, 2, 3, 4, 6, 8, 11, 16, 23, 33, 48, 70, 101, 147, 213};

enum class ConeRayCasterStatus : std::uint8_t {
  ok = 0,
  bad_grid,   // empty or invalid grid, or larger than the storage
  bad_bins,   // T is not a power of two in [8, the storage's T]
};

namespace detail {
#if defined(__x86_64__)
// Whether this CPU runs AVX2 (the cone caster's eight-lane walk): a bit libgcc's start-up read from cpuid.
inline bool has_avx2() { return __builtin_cpu_supports("avx2"); }
#endif
struct ConeTables {
  const float* cos_b = nullptr;          // [T] cos of heading b
  const float* sin_b = nullptr;          // [T]
  const std::uint8_t* entry = nullptr;   // [T][H][W] bytes, or packed: [T / 2][H][W], bin 2p + 1 in the high half
  std::int32_t bins = 0;
  float min_cos_gap = 1.0f;  // cos of 1.2 bins' halves: a heading further from the ray's is replaced by the ray's
};
}  // namespace detail

// Read-only view over a built table: ConeRayCaster over bytes, PackedConeRayCaster over 4-bit codes (kConeLevels).
template <bool Packed>
class BasicConeRayCaster {
 public:
  using Tables = detail::ConeTables;

  BasicConeRayCaster() = default;
  BasicConeRayCaster(const OccupancyGrid& grid, const Tables& t)
      : grid_(grid), t_(t), mask_(static_cast<std::uint32_t>(t.bins - 1)),
        bins_per_rad_(static_cast<float>(t.bins) / kTwoPi),
        cells_(static_cast<std::uint32_t>(grid.width()) * static_cast<std::uint32_t>(grid.height())) {}

  bool valid() const { return grid_.valid() && t_.bins > 0 && t_.entry != nullptr; }
  const OccupancyGrid& grid() const { return grid_; }
  std::int32_t bins() const { return t_.bins; }
  float bins_per_rad() const { return bins_per_rad_; }

  // The caster interface of GridRayCaster ((dx, dy) a unit vector): one atan2 to pick the heading.
  float cast(float x, float y, float dx, float dy, float max_range) const {
    if (!fmath::isfinite(dx) || !fmath::isfinite(dy)) return 0.0f;
    return cast_from(origin(x, y), dx, dy, fmath::atan2(dy, dx) * bins_per_rad_, max_range);
  }

  // The stored bound of heading bin b at cell (cx, cy), in cells: no ray from the cell's square at a heading within
  // 1.25 bins' halves of b enters an occupied cell before it. -1 for an occupied cell or arguments off the table.
  std::int32_t bound_cells(std::int32_t b, std::int32_t cx, std::int32_t cy) const {
    if (!valid() || b < 0 || b >= t_.bins || !grid_.contains(cx, cy)) return -1;
    const std::uint32_t i = static_cast<std::uint32_t>(cy * grid_.width() + cx), ub = static_cast<std::uint32_t>(b);
    return static_cast<std::int32_t>(entry(plane(ub), shift(ub), i)) - 1;
  }

  // A start shared by many rays (the beam model's sensor position): its cell, found once, and whether rays from it
  // are walked at all (inside the map, not in an occupied cell: otherwise every cast from it returns 0).
  struct Origin {
    detail::GridRay ray{};
    bool walk = false;
  };
  Origin origin(float x, float y) const {
    Origin o;
    o.walk = o.ray.start(grid_, x, y) && !grid_.is_occupied_value(grid_.at(o.ray.ix, o.ray.iy));
    return o;
  }

  // heading_bins: the ray's heading in bins (heading * bins_per_rad()), any value within +-2^20; (dx, dy) its unit
  // vector. A heading more than 1.2 bins' halves from the ray's is not trusted: the ray's own is taken (an atan2).
  // Always inlined: GCC for the Cortex-M kept it a call, whose prologue and reloads of the members cost 17
  // instructions per particle-beam on the M4F (bench_mcl: 540 -> 523); on the host it was inlined already.
  [[gnu::always_inline]] float cast_from(const Origin& o, float dx, float dy, float heading_bins,
                                         float max_range) const {
    if (!o.walk) return 0.0f;
    // Not a unit vector (nor finite: NaN and inf fail the compare), or no range: refused, as aim() would.
    if (!(fmath::abs(dx) <= 1.5f && fmath::abs(dy) <= 1.5f && max_range > 0.0f)) return 0.0f;
    detail::GridRay r = o.ray;
    r.aim_checked(grid_, dx, dy, max_range);
    const float f = heading_bins + 0.5f + 1048576.0f;
    const std::uint32_t b = trusted_bin((f >= 0.0f && f < 2097152.0f) ? static_cast<std::uint32_t>(f) & mask_ : 0u,
                                        dx, dy);
    const std::uint8_t* q = plane(b);
    const std::uint32_t sh = shift(b);
    const std::int32_t w = grid_.width(), h = grid_.height();
    // The walk reads codes (an entry, or a packed entry's code: 0 and 1 the same, a jump code >= 2 too).
    std::uint32_t e = code(q, sh, static_cast<std::uint32_t>(r.iy * w + r.ix));
    float t = 0.0f;
    const std::int32_t bound = 3 * (w + h) + 8;
    // The walk ends at max_range or where the ray leaves the map, whichever is first: a step whose t reaches
    // t_exit() has left the map, one below it has not (the same float), so neither move checks the cell against the
    // map. A jump adds e - 1 - 1/64 cells to t and lands where the ray is then (GridRay::land_inside()); an exact step
    // is GridRay::step(), from the cell's index. The landing's rounding is far inside the 1/64 cell of slack the
    // entries keep.
    const float t_exit = r.t_exit(w, h), t_end = r.t_max < t_exit ? r.t_max : t_exit;
    for (std::int32_t n = bound; n > 0; --n) {  // counted down: one compare fewer a move on the boards
      if (e >= 2u) {
        t += jump_cells(e);
        if (!(t < t_end)) return max_range;
        r.land_inside(t, w, h);
      } else {
        t = r.step();
        if (!(t < t_end)) return max_range;
      }
      e = code(q, sh, static_cast<std::uint32_t>(r.iy * w + r.ix));
      if (e == 0u) return detail::cells_to_range(t, grid_.resolution(), max_range);
    }
    return max_range;
  }

#if defined(__x86_64__)
  // 8 G casts_from() at once (G groups of eight), out[i] the float of cast_from(o, dx[i], dy[i], heading_bins[i],
  // max_range), bit for bit: on a CPU with AVX2 the rays walked in eight lanes a register, each lane taking its jump
  // or its step by blends (the same float and integer operations), every group moved once a round, so the groups'
  // table reads are in flight together where one ray's reads are a chain; otherwise one ray at a time.
  template <std::uint32_t G>
  void cast_lanes_from(const Origin& o, const float* dx, const float* dy, const float* heading_bins, float max_range,
                       float* out, std::uint32_t groups = G) const {
    if (groups <= G && grid_.width() < 32768 && grid_.height() < 32768 && lanes_vectorized()) {
      walk_lanes<G>(o, dx, dy, heading_bins, max_range, out, groups);
      return;
    }
    for (std::uint32_t i = 0; i < 8 * groups; ++i) out[i] = cast_from(o, dx[i], dy[i], heading_bins[i], max_range);
  }
  // Whether cast_lanes_from() walks in lanes on this CPU (AVX2).
  static bool lanes_vectorized() { return detail::has_avx2(); }
#endif

 private:
  // A jump of entry e is e - kJumpShort cells: the bound e - 1 less 1/64 cell of slack for rounding.
  static constexpr float kJumpShort = 1.0f + 1.0f / 64.0f;

  // Bin b of the ray's heading as given, or the ray's own (an atan2) when (dx, dy) is more than 1.2 bins' halves from
  // it: the bound is for the cone of the bin it is read from.
  std::uint32_t trusted_bin(std::uint32_t b, float dx, float dy) const {
    if (t_.cos_b[b] * dx + t_.sin_b[b] * dy >= t_.min_cos_gap) return b;
    return static_cast<std::uint32_t>(fmath::atan2(dy, dx) * bins_per_rad_ + 0.5f + 1048576.0f) & mask_;
  }

#if defined(__x86_64__)
#define EST_AVX2 __attribute__((target("avx2"), always_inline))
  using V = __m256;   // eight floats
  using M = __m256i;  // eight int32, or eight masks (-1 true, 0 false)
  // Eight rays' walk: their cells, parameters, entries, and what each ray was aimed with.
  struct Lanes {
    M ix, iy, e, act, sx, sy, ax, ay;
    V t, dx, dy, idx, idy, nx, ny, res, end;
    const std::uint8_t* q[8];
    std::uint32_t sh[8];
  };
  // What the rays share: their start, the map, the range.
  struct Walk {
    M wv, wl, hl;  // w for the index's product; the last column and row
    V gx, gy, res_cell, mr;
  };
  // Float compares as C's (false on NaN) as masks, blends, the cast between the two.
  EST_AVX2 static M as_m(V v) { return _mm256_castps_si256(v); }
  EST_AVX2 static V as_v(M m) { return _mm256_castsi256_ps(m); }
  EST_AVX2 static M lt(V a, V b) { return as_m(_mm256_cmp_ps(a, b, _CMP_LT_OQ)); }
  EST_AVX2 static M le(V a, V b) { return as_m(_mm256_cmp_ps(a, b, _CMP_LE_OQ)); }
  EST_AVX2 static M gt(V a, V b) { return as_m(_mm256_cmp_ps(a, b, _CMP_GT_OQ)); }
  EST_AVX2 static M ge(V a, V b) { return as_m(_mm256_cmp_ps(a, b, _CMP_GE_OQ)); }
  EST_AVX2 static M both(M a, M b) { return _mm256_and_si256(a, b); }
  EST_AVX2 static M sel(M m, M a, M b) { return _mm256_blendv_epi8(b, a, m); }
  EST_AVX2 static V sel(M m, V a, V b) { return _mm256_blendv_ps(b, a, as_v(m)); }
  EST_AVX2 static int lanes_of(M m) { return _mm256_movemask_ps(as_v(m)); }

  template <std::uint32_t G>
  __attribute__((target("avx2"))) void walk_lanes(const Origin& o, const float* dx, const float* dy,
                                                  const float* heading_bins, float max_range, float* out,
                                                  std::uint32_t groups) const {
    const std::int32_t w = grid_.width(), h = grid_.height();
    Lanes g[G];
    const detail::GridRay& r = o.ray;
    // aim()'s refusals for all: no walk from here, or no range.
    const bool walk = o.walk && max_range > 0.0f;
    const std::uint32_t start = walk ? static_cast<std::uint32_t>(r.iy * w + r.ix) : 0u;
    const V limit = _mm256_set1_ps(1.5f), abs_mask = as_v(_mm256_set1_epi32(0x7fffffff));
    const V tiny = _mm256_set1_ps(1e-9f), mtiny = _mm256_set1_ps(-1e-9f);
    const M zero = _mm256_setzero_si256();
    int active = 0;
    const V gx = _mm256_set1_ps(r.gx), gy = _mm256_set1_ps(r.gy);
    const V t_max = _mm256_set1_ps(max_range * grid_.inv_resolution());  // aim()'s, the same for every ray
    for (std::uint32_t k = 0; k < groups; ++k) {
      Lanes& l = g[k];
      const V vdx = _mm256_loadu_ps(dx + 8 * k), vdy = _mm256_loadu_ps(dy + 8 * k);
      // Finite with |d| <= 1.5 (NaN and inf fail the compare): aim()'s and cast_from()'s other refusals.
      M ok = both(le(_mm256_and_ps(vdx, abs_mask), limit), le(_mm256_and_ps(vdy, abs_mask), limit));
      if (!walk) ok = zero;
      // aim(): the steps' signs (a compare's mask is -1), where the next boundary is, the inverse directions; a
      // crossing never taken (no step on the axis) gets the floor kNever, the others -inf (move()'s max).
      const M gtx = gt(vdx, tiny), ltx = lt(vdx, mtiny), gty = gt(vdy, tiny), lty = lt(vdy, mtiny);
      const M stepx = _mm256_or_si256(gtx, ltx), stepy = _mm256_or_si256(gty, lty);
      l.sx = _mm256_sub_epi32(ltx, gtx);
      l.sy = _mm256_sub_epi32(lty, gty);
      l.ax = _mm256_sub_epi32(zero, gtx);
      l.ay = _mm256_sub_epi32(zero, gty);
      const V one = _mm256_set1_ps(1.0f);
      l.idx = _mm256_and_ps(as_v(stepx), _mm256_div_ps(one, vdx));
      l.idy = _mm256_and_ps(as_v(stepy), _mm256_div_ps(one, vdy));
      const V never = _mm256_set1_ps(detail::GridRay::kNever), below = _mm256_set1_ps(-__builtin_inff());
      l.nx = sel(stepx, below, never);
      l.ny = sel(stepy, below, never);
      // min(t_max, t_exit()): the map's edge ahead (w or 0 columns, h or 0 rows) as the step crosses it.
      const V ex = _mm256_max_ps(
          _mm256_mul_ps(_mm256_sub_ps(_mm256_cvtepi32_ps(both(gtx, _mm256_set1_epi32(w))), gx), l.idx), l.nx);
      const V ey = _mm256_max_ps(
          _mm256_mul_ps(_mm256_sub_ps(_mm256_cvtepi32_ps(both(gty, _mm256_set1_epi32(h))), gy), l.idy), l.ny);
      l.end = _mm256_min_ps(t_max, _mm256_min_ps(ex, ey));
      l.dx = vdx;
      l.dy = vdy;
      // The heading bin as cast_from() picks it; the table's planes and the start's entries one lane at a time.
      const V f = _mm256_add_ps(_mm256_add_ps(_mm256_loadu_ps(heading_bins + 8 * k), _mm256_set1_ps(0.5f)),
                                _mm256_set1_ps(1048576.0f));
      const M in = both(ge(f, _mm256_setzero_ps()), lt(f, _mm256_set1_ps(2097152.0f)));
      alignas(32) std::uint32_t b0[8];
      alignas(32) std::int32_t ok0[8], e0[8];
      const M bins = both(_mm256_cvttps_epi32(f), _mm256_set1_epi32(static_cast<std::int32_t>(mask_)));
      _mm256_store_si256(reinterpret_cast<M*>(b0), both(in, bins));
      _mm256_store_si256(reinterpret_cast<M*>(ok0), ok);
      for (std::uint32_t j = 0; j < 8; ++j) {
        const std::uint32_t i = 8 * k + j;
        const std::uint32_t bj = ok0[j] != 0 ? trusted_bin(b0[j], dx[i], dy[i]) : b0[j];
        l.q[j] = plane(bj);
        l.sh[j] = shift(bj);
        e0[j] = static_cast<std::int32_t>(entry(l.q[j], l.sh[j], start));
      }
      l.e = _mm256_load_si256(reinterpret_cast<const M*>(e0));
      l.act = ok;
      l.res = _mm256_and_ps(as_v(ok), _mm256_set1_ps(max_range));
      l.ix = _mm256_set1_epi32(r.ix);
      l.iy = _mm256_set1_epi32(r.iy);
      l.t = _mm256_setzero_ps();
      active |= lanes_of(ok);
    }
    if (active != 0) {
      Walk c;
      c.gx = gx;
      c.gy = gy;
      c.wv = _mm256_set1_epi32(w);
      c.wl = _mm256_set1_epi32(w - 1);
      c.hl = _mm256_set1_epi32(h - 1);
      c.res_cell = _mm256_set1_ps(grid_.resolution());
      c.mr = _mm256_set1_ps(max_range);
      const std::int32_t bound = 3 * (w + h) + 8;
      for (std::int32_t n = 0; n < bound; ++n) {
        bool any = false;
        for (std::uint32_t k = 0; k < groups; ++k) any |= move(g[k], c);
        if (!any) break;
      }
    }
    for (std::uint32_t k = 0; k < groups; ++k) _mm256_storeu_ps(out + 8 * k, g[k].res);
  }

  // One move of each walked lane of l (cast_from()'s loop body); false when none was walked.
  __attribute__((target("avx2"))) static bool move(Lanes& l, const Walk& c) {
    M act = l.act;
    const int walked = lanes_of(act);
    if (walked == 0) return false;
    const M e = l.e, ix = l.ix, iy = l.iy;
    const M jump = _mm256_cmpgt_epi32(e, _mm256_set1_epi32(1));
    // The jump: t + e - 1 - 1/64 cells, landed as GridRay::land_inside() (a lane whose t reaches its end is not
    // walked on, whatever its cell).
    auto jumps = [&](M& jx, M& jy, V& tj) EST_AVX2 {
      tj = _mm256_add_ps(l.t, _mm256_sub_ps(_mm256_cvtepi32_ps(e), _mm256_set1_ps(kJumpShort)));
      jx = _mm256_min_epi32(_mm256_cvttps_epi32(_mm256_add_ps(c.gx, _mm256_mul_ps(tj, l.dx))), c.wl);
      jy = _mm256_min_epi32(_mm256_cvttps_epi32(_mm256_add_ps(c.gy, _mm256_mul_ps(tj, l.dy))), c.hl);
      return lt(tj, l.end);
    };
    // The step: GridRay::step(). A crossing never taken (inverse 0) is raised to kNever by the max with the lane's
    // floor; min(tx, ty) is tx < ty ? tx : ty.
    auto steps = [&](M& sx, M& sy, V& ts) EST_AVX2 {
      const V tx = _mm256_max_ps(
          _mm256_mul_ps(_mm256_sub_ps(_mm256_cvtepi32_ps(_mm256_add_epi32(ix, l.ax)), c.gx), l.idx), l.nx);
      const V ty = _mm256_max_ps(
          _mm256_mul_ps(_mm256_sub_ps(_mm256_cvtepi32_ps(_mm256_add_epi32(iy, l.ay)), c.gy), l.idy), l.ny);
      const M xs = lt(tx, ty);
      sx = _mm256_add_epi32(ix, both(xs, l.sx));
      sy = _mm256_add_epi32(iy, _mm256_andnot_si256(xs, l.sy));
      ts = _mm256_min_ps(tx, ty);
      return lt(ts, l.end);
    };
    // Each lane's move; a lane that leaves keeps max_range and stops. A lane no longer walked may hold any cell: its
    // read is of cell 0. When every walked lane jumps, or every one steps, the other move is not computed.
    const int jumping = lanes_of(jump) & walked;
    M nix, niy;
    V t;
    if (jumping == walked) {
      act = both(act, jumps(nix, niy, t));
    } else if (jumping == 0) {
      act = both(act, steps(nix, niy, t));
    } else {
      M jx, jy, sx, sy;
      V tj, ts;
      const M okj = jumps(jx, jy, tj), oks = steps(sx, sy, ts);
      act = both(act, sel(jump, okj, oks));
      nix = sel(jump, jx, sx);
      niy = sel(jump, jy, sy);
      t = sel(jump, tj, ts);
    }
    l.ix = nix;
    l.iy = niy;
    l.t = t;
    // The cell's index iy w + ix: iy < h < 2^15 and w < 2^15 (cast_lanes_from() checks), so one 16 x 16-bit product;
    // the eight reads one lane at a time.
    alignas(32) std::uint32_t i[8];
    _mm256_store_si256(reinterpret_cast<M*>(i), both(act, _mm256_add_epi32(_mm256_madd_epi16(niy, c.wv), nix)));
    auto read = [&](std::uint32_t j) { return static_cast<std::int32_t>(entry(l.q[j], l.sh[j], i[j])); };
    const M ne = _mm256_setr_epi32(read(0), read(1), read(2), read(3), read(4), read(5), read(6), read(7));
    l.e = ne;
    const M hit = both(act, _mm256_cmpeq_epi32(ne, _mm256_setzero_si256()));
    l.res = sel(hit, _mm256_min_ps(_mm256_mul_ps(t, c.res_cell), c.mr), l.res);  // cells_to_range()
    l.act = _mm256_andnot_si256(hit, act);
    return true;
  }
#undef EST_AVX2
#endif

  // Heading b's plane of the table, and the place of its half in a packed byte.
  const std::uint8_t* plane(std::uint32_t b) const { return t_.entry + (Packed ? b >> 1 : b) * cells_; }
  static std::uint32_t shift(std::uint32_t b) { return Packed ? (b & 1u) * 4u : 0u; }
  // The entry of cell i in a plane q; code() the same for bytes, a packed entry's code (its level kConeLevels[c]).
  static std::uint32_t entry(const std::uint8_t* q, std::uint32_t sh, std::uint32_t i) {
    if (Packed) return kConeLevels[code(q, sh, i)];
    return q[i];
  }
  static std::uint32_t code(const std::uint8_t* q, std::uint32_t sh, std::uint32_t i) {
    if (Packed) return (static_cast<std::uint32_t>(q[i]) >> sh) & 15u;
    return q[i];
  }
  // The jump of a code >= 2, in cells: its entry e - kJumpShort, the same float; for a packed code from a table of
  // them (one load where the level's load, its conversion and the subtraction took three instructions on the M4F).
  static float jump_cells(std::uint32_t c) {
    if (Packed) return kJumps.cells[c];
    return static_cast<float>(c) - kJumpShort;
  }
  struct Jumps {
    float cells[16];
  };
  static constexpr Jumps jumps_of_levels() {
    Jumps j{};
    for (std::uint32_t c = 2; c < 16; ++c) j.cells[c] = static_cast<float>(kConeLevels[c]) - kJumpShort;
    return j;
  }
  static constexpr Jumps kJumps = jumps_of_levels();  // codes 0 and 1 are no jump: 0

  OccupancyGrid grid_{};
  Tables t_{};
  std::uint32_t mask_ = 0;
  float bins_per_rad_ = 0.0f;
  std::uint32_t cells_ = 0;
};
using ConeRayCaster = BasicConeRayCaster<false>;
using PackedConeRayCaster = BasicConeRayCaster<true>;

// Runtime-capacity interface over caller-owned arrays.
class ConeRayCasterBuffer {
 public:
  ConeRayCasterBuffer(const ConeRayCasterBuffer&) = delete;
  ConeRayCasterBuffer& operator=(const ConeRayCasterBuffer&) = delete;

  // Columns (and rows) scanned directly before the bound continues from the cells beyond them.
  static constexpr std::int32_t kDirect = 16;

  // Bytes the query reads: one per cell and heading (half of one packed), 8 per heading.
  std::uint32_t bytes_used() const {
    const std::uint32_t bins = static_cast<std::uint32_t>(bins_);
    return (packed_ ? bins / 2u : bins) * cells_ + 8u * bins;
  }

  // Builds the table of T headings 2 pi b / T for `grid`. Nothing usable is left unless the result is ok (view()
  // is invalid then). Bounded: per heading, (kDirect + 1) prefix-count reads and a window of entries per cell.
  ConeRayCasterStatus build(const OccupancyGrid& grid, std::int32_t bins) {
    grid_ = OccupancyGrid{};
    tables_ = detail::ConeTables{};
    bins_ = 0;
    cells_ = 0;
    if (!grid.valid() || grid.width() > cap_w_ || grid.height() > cap_h_) return ConeRayCasterStatus::bad_grid;
    if (bins < 8 || bins > cap_bins_ || (bins & (bins - 1)) != 0) return ConeRayCasterStatus::bad_bins;
    const std::int32_t w = grid.width(), hgt = grid.height();
    const std::uint32_t cells = static_cast<std::uint32_t>(w) * static_cast<std::uint32_t>(hgt);
    // Prefix counts of occupied cells: along each column (x fixed, over y) and along each row (y fixed, over x).
    for (std::int32_t x = 0; x < w; ++x) {
      std::uint16_t* p = col_ + static_cast<std::uint32_t>(x) * static_cast<std::uint32_t>(hgt + 1);
      p[0] = 0;
      for (std::int32_t y = 0; y < hgt; ++y)
        p[y + 1] = static_cast<std::uint16_t>(p[y] + (grid.is_occupied_value(grid.at(x, y)) ? 1 : 0));
    }
    for (std::int32_t y = 0; y < hgt; ++y) {
      std::uint16_t* p = row_ + static_cast<std::uint32_t>(y) * static_cast<std::uint32_t>(w + 1);
      p[0] = 0;
      for (std::int32_t x = 0; x < w; ++x)
        p[x + 1] = static_cast<std::uint16_t>(p[x] + (grid.is_occupied_value(grid.at(x, y)) ? 1 : 0));
    }
    const float half = kTwoPi / static_cast<float>(bins) * 0.5f;
    for (std::int32_t b = 0; b < bins; ++b) {
      const float a = kTwoPi * static_cast<float>(b) / static_cast<float>(bins);
      float s = 0.0f, c = 0.0f;
      fmath::sincos(a, s, c);
      cos_[b] = c;
      sin_[b] = s;
      // The cone's edges: 1.25 halves of a bin each side (the query trusts 1.2).
      float s_lo = 0.0f, c_lo = 0.0f, s_hi = 0.0f, c_hi = 0.0f;
      fmath::sincos(a - 1.25f * half, s_lo, c_lo);
      fmath::sincos(a + 1.25f * half, s_hi, c_hi);
      const bool x_major = fmath::abs(c) >= fmath::abs(s);
      Axis ax;
      if (x_major) {
        // Lines are columns (u = x), across them y; the slope dy / |dx| is monotone over the cone.
        const float m0 = slope(s_lo, c_lo), m1 = slope(s_hi, c_hi);
        ax = Axis{c > 0.0f ? 1 : -1, w, hgt, col_, smaller(m0, m1), larger(m0, m1), largest_abs(c_lo, c_hi, c),
                  true};
      } else {
        const float m0 = slope(c_lo, s_lo), m1 = slope(c_hi, s_hi);
        ax = Axis{s > 0.0f ? 1 : -1, hgt, w, row_, smaller(m0, m1), larger(m0, m1), largest_abs(s_lo, s_hi, s),
                  false};
      }
      const std::uint32_t ub = static_cast<std::uint32_t>(b);
      if (packed_)
        build_bin<true>(ax, entry_ + (ub >> 1) * cells, (ub & 1u) * 4u);
      else
        build_bin<false>(ax, entry_ + ub * cells, 0u);
    }
    bins_ = bins;
    cells_ = cells;
    detail::ConeTables t;
    t.cos_b = cos_;
    t.sin_b = sin_;
    t.entry = entry_;
    t.bins = bins;
    float sg = 0.0f, cg = 1.0f;
    fmath::sincos(1.2f * half, sg, cg);
    t.min_cos_gap = cg;
    grid_ = grid;
    tables_ = t;
    return ConeRayCasterStatus::ok;
  }
  // The view of a byte table (invalid over a packed one, or before a build), and of a packed one (the reverse).
  ConeRayCaster view() const { return packed_ ? ConeRayCaster{} : ConeRayCaster(grid_, tables_); }
  PackedConeRayCaster packed_view() const {
    return packed_ ? PackedConeRayCaster(grid_, tables_) : PackedConeRayCaster{};
  }

 protected:
  // entries: cap_bins x cap_w x cap_h bytes, or half that when packed.
  ConeRayCasterBuffer(float* cos_b, float* sin_b, std::int32_t cap_bins, std::uint8_t* entries, std::int32_t cap_w,
                      std::int32_t cap_h, std::uint16_t* col, std::uint16_t* row, float* line, std::uint8_t* bound,
                      bool packed = false)
      : cos_(cos_b), sin_(sin_b), cap_bins_(cap_bins), entry_(entries), packed_(packed), cap_w_(cap_w), cap_h_(cap_h),
        col_(col), row_(row), line_(line), bound_(bound) {}
  ~ConeRayCasterBuffer() = default;

 private:
  struct Axis {
    std::int32_t su;       // +1 or -1: the direction along u
    std::int32_t nu, nv;   // lines, and cells per line
    const std::uint16_t* prefix;  // [nu][nv + 1]
    float m_lo, m_hi;      // the slope dv / |du| over the cone
    float max_cos;         // the largest |du| per unit path over the cone
    bool x_major;
  };
  static float slope(float across, float along) { return across / fmath::abs(along); }
  static float largest_abs(float a, float b, float c) {
    const float m = fmath::abs(a) > fmath::abs(b) ? fmath::abs(a) : fmath::abs(b);
    return m > fmath::abs(c) ? m : fmath::abs(c);
  }
  static std::int32_t floor_i(float v) {
    const std::int32_t i = static_cast<std::int32_t>(v);
    return static_cast<float>(i) > v ? i - 1 : i;
  }
  // The rows (across the lines) a cone from a cell's square reaches after a run in [lo, hi] along u: offsets from
  // the cell's own row, widened by 1/1024 cell against rounding.
  static void rows(const Axis& a, float run_lo, float run_hi, std::int32_t& r0, std::int32_t& r1) {
    const float lo = smaller(run_lo * a.m_lo, run_hi * a.m_lo);
    const float hi = 1.0f + larger(run_lo * a.m_hi, run_hi * a.m_hi);
    r0 = floor_i(lo - 1.0f / 1024.0f);
    r1 = floor_i(hi + 1.0f / 1024.0f);
  }
  static float smaller(float a, float b) { return a < b ? a : b; }
  static float larger(float a, float b) { return a > b ? a : b; }

  // The lines' bounds in cells (0 for an occupied cell), line after line along u: what the cells beyond a line's
  // first kDirect + 1 lines read. A copy of the table's entries less one, kept because an x-major bin's lines are
  // the table's columns, and the window read across them would stride a whole row per cell.
  std::uint8_t* bound_line(std::int32_t u, std::int32_t nv) const {
    return bound_ + static_cast<std::uint32_t>(u) * static_cast<std::uint32_t>(nv);
  }

  // For every v of a line: d[v] = min(d[v], value) where the window [v + w0, v + w1] (clipped to the line) holds an
  // occupied cell, read from a prefix count p. The interior, where no clipping is needed, is a plain loop.
  static void mark_hits(float* d, const std::uint16_t* p, std::int32_t nv, std::int32_t w0, std::int32_t w1,
                        float value) {
    std::int32_t va = -w0 > 0 ? -w0 : 0, vb = nv - 1 - w1;  // interior [va, vb]
    if (vb > nv - 1) vb = nv - 1;
    for (std::int32_t v = 0; v < nv; ++v) {
      if (v == va && va <= vb) {
        const std::uint16_t* hi = p + (va + w1 + 1);
        const std::uint16_t* lo = p + (va + w0);
        for (std::int32_t i = 0; i <= vb - va; ++i) {
          const float m = d[va + i] < value ? d[va + i] : value;
          d[va + i] = hi[i] != lo[i] ? m : d[va + i];
        }
        v = vb;
        continue;
      }
      std::int32_t lo = v + w0, hi = v + w1;
      if (lo < 0) lo = 0;
      if (hi > nv - 1) hi = nv - 1;
      if (lo <= hi && p[hi + 1] != p[lo] && value < d[v]) d[v] = value;
    }
  }
  // For every v: d[v] = min(d[v], add + the smallest bound of the window [v + w0, v + w1] of line `beyond`
  // (clipped to the line; nothing where the window is empty), one window offset at a time.
  static void mark_beyond(float* d, const std::uint8_t* beyond, std::int32_t nv, std::int32_t w0, std::int32_t w1,
                          float add) {
    for (std::int32_t k = w0; k <= w1; ++k) {
      const std::int32_t va = -k > 0 ? -k : 0, vb = nv - 1 - k < nv - 1 ? nv - 1 - k : nv - 1;  // v + k on the line
      for (std::int32_t v = va; v <= vb; ++v) {
        const float via = add + static_cast<float>(beyond[v + k]);
        d[v] = via < d[v] ? via : d[v];
      }
    }
  }

  // The code of entry e: the largest level not above it.
  static std::uint8_t code_of(std::uint32_t e) {
    std::uint8_t c = 0;
    for (std::uint8_t k = 1; k < 16; ++k)
      if (kConeLevels[k] <= e) c = k;
    return c;
  }

  template <bool Packed>
  void build_bin(const Axis& a, std::uint8_t* e, std::uint32_t shift) const {
    const float path_per_run = 1.0f / a.max_cos;  // path >= run / max|cos|
    std::int32_t r0[kDirect + 1], r1[kDirect + 1];
    for (std::int32_t i = 0; i <= kDirect; ++i) {
      rows(a, static_cast<float>(i > 0 ? i - 1 : 0), static_cast<float>(i + 1), r0[i], r1[i]);
    }
    std::int32_t h0 = 0, h1 = 0;  // rows through which the cone enters line k + 1
    rows(a, static_cast<float>(kDirect), static_cast<float>(kDirect + 1), h0, h1);
    const std::uint32_t stride = static_cast<std::uint32_t>(a.nv + 1);
    const std::uint32_t w = static_cast<std::uint32_t>(a.x_major ? a.nu : a.nv);
    // Lines in the order the bound needs them: the farthest along the heading first.
    for (std::int32_t n = 0; n < a.nu; ++n) {
      const std::int32_t u = a.su > 0 ? a.nu - 1 - n : n;
      float* d = line_;
      for (std::int32_t v = 0; v < a.nv; ++v) d[v] = 254.0f;  // the cone leaves the map without an obstacle
      for (std::int32_t i = 0; i <= kDirect; ++i) {
        const std::int32_t ui = u + a.su * i;
        if (ui < 0 || ui >= a.nu) break;
        mark_hits(d, a.prefix + static_cast<std::uint32_t>(ui) * stride, a.nv, r0[i], r1[i],
                  static_cast<float>(i > 0 ? i - 1 : 0) * path_per_run);
      }
      const std::int32_t un = u + a.su * (kDirect + 1);
      if (un >= 0 && un < a.nu)
        mark_beyond(d, bound_line(un, a.nv), a.nv, h0, h1, static_cast<float>(kDirect) * path_per_run);
      std::uint8_t* out_line = bound_line(u, a.nv);
      const std::uint16_t* own = a.prefix + static_cast<std::uint32_t>(u) * stride;  // occupied: the count steps
      for (std::int32_t v = 0; v < a.nv; ++v) {
        const std::int32_t x = a.x_major ? u : v, y = a.x_major ? v : u;
        const bool occupied = own[v + 1] != own[v];
        const std::int32_t di = d[v] >= 254.0f ? 254 : static_cast<std::int32_t>(d[v]);  // floor
        out_line[v] = occupied ? std::uint8_t{0} : static_cast<std::uint8_t>(di);
        const std::uint8_t byte = occupied ? std::uint8_t{0} : static_cast<std::uint8_t>(di + 1);
        std::uint8_t& out = e[static_cast<std::uint32_t>(y) * w + static_cast<std::uint32_t>(x)];
        if (Packed)
          out = static_cast<std::uint8_t>((static_cast<std::uint32_t>(out) & ~(15u << shift)) |
                                          (static_cast<std::uint32_t>(code_of(byte)) << shift));
        else
          out = byte;
      }
    }
  }

  float* cos_;
  float* sin_;
  std::int32_t cap_bins_;
  std::uint8_t* entry_;
  bool packed_;
  std::int32_t cap_w_, cap_h_;
  std::uint16_t* col_;
  std::uint16_t* row_;
  float* line_;
  std::uint8_t* bound_;
  std::uint32_t cells_ = 0;
  std::int32_t bins_ = 0;
  OccupancyGrid grid_{};
  detail::ConeTables tables_{};
};

// The owner: up to TMax headings over a map of up to MaxW x MaxH cells, Bits (8, or 4 packed) per cell and heading;
// a static object.
template <std::int32_t TMax, std::int32_t MaxW, std::int32_t MaxH, std::int32_t Bits = 8>
class ConeRayCasterStorage final : public ConeRayCasterBuffer {
  static_assert(TMax >= 8 && TMax <= 1024 && (TMax & (TMax - 1)) == 0, "T must be a power of two >= 8");
  static_assert(Bits == 8 || Bits == 4, "8 bits per cell and heading, or 4 packed");
  static_assert(MaxW > 0 && MaxH > 0 && MaxW < 65535 && MaxH < 65535, "map size");
  static constexpr std::uint64_t kT = static_cast<std::uint64_t>(TMax);
  static constexpr std::uint64_t kW = static_cast<std::uint64_t>(MaxW);
  static constexpr std::uint64_t kH = static_cast<std::uint64_t>(MaxH);

 public:
  static constexpr std::uint64_t kCells = kW * kH;
  // The query's table and headings, then the build's scratch.
  static constexpr std::uint64_t kBytes =
      kCells * kT * Bits / 8u + 8ull * kT + 2ull * (kW * (kH + 1u) + kH * (kW + 1u)) + 4ull * (kW > kH ? kW : kH) +
      kCells;
  ConeRayCasterStorage()
      : ConeRayCasterBuffer(cos_, sin_, TMax, entry_storage_, MaxW, MaxH, col_storage_, row_storage_,
                            line_storage_, bound_storage_, Bits == 4) {}
  // ConeRayCaster, or PackedConeRayCaster for Bits = 4.
  auto view() const {
    if constexpr (Bits == 4)
      return packed_view();
    else
      return ConeRayCasterBuffer::view();
  }

 private:
  float cos_[kT];
  float sin_[kT];
  std::uint8_t entry_storage_[kCells * kT * Bits / 8u];
  std::uint16_t col_storage_[kW * (kH + 1u)];
  std::uint16_t row_storage_[kH * (kW + 1u)];
  float line_storage_[kW > kH ? kW : kH];
  std::uint8_t bound_storage_[kCells];
};

}  // namespace est
