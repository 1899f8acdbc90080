#pragma once
// Exact ray casting by per-heading lanes of obstacle cells, for the beam model's z* (Thrun table 6.1, line 3): the
// answer of GridRayCaster (ray_casting.hpp) at any position and any heading, found by a binary search instead of a
// walk. The idea is RangeLibc's compressed directional distance transform (Walsh and Karaman, "CDDT: Fast
// approximate 2D ray casting for accelerated localization", 2018): for each of T discretized headings, rotate the
// map so the heading is the u axis, cut it into lanes one cell wide across it (s axis), and keep per lane the
// sorted positions along u of the obstacle cells it crosses ("zero points"). CDDT answers from the zero points
// alone and so is approximate (the heading is quantized, a lane is wider than a ray). Here the zero points are
// only candidates, each checked exactly:
//  - a lane entry is an occupied cell whose square overlaps the lane (widened by 1/64 cell against rounding),
//    keyed by the smallest u of the square (floor, 1/16 cell), a lower bound of where any ray can enter it;
//  - a query at heading a uses the nearest table heading b (|a - b| <= pi / T) and follows the ray through the
//    lanes it crosses (its lateral drift is t sin(a - b), about 1.5 lanes over 60 cells at T = 64); in each lane a
//    block index (the first entry of every block of u) and a few steps find the first candidate that can be entered
//    after the ray reached the lane, and the candidates are tested in key order with the exact slab test until the
//    key passes the best entry found;
//  - the slab test computes a face crossing with GridRayCaster's own expression ((face - gx) / dx from the same gx
//    and 1 / dx), and breaks a tie at a cell corner as its traversal does (the y step first), so the result is the
//    same float as the exact traversal's.
// Only cells a ray can enter first are stored: occupied cells with a non-occupied face neighbour on a side the
// table heading's rays (+- 3/4 bin) can come from; a ray enters a cell through a face, so a cell walled on those
// sides is always entered after the wall.
//
// Conventions are GridRayCaster's: unknown cells are free; a start in an occupied cell, outside the map or
// non-finite returns 0; no hit before max_range or the map's edge returns max_range.
// Accuracy (tests/test_lane_ray_caster.cpp prints it and requires >= 99.9 % within one cell): the same float as
// GridRayCaster on every ray tested, worst error 0 m: 20 000 random rays (free starts, continuous headings) per case
// on the synthetic office (16, 64, 256 headings; 2 and 20 m) and the Intel map (64, 128 headings; 5 and 30 m), and
// 17 096 rays from cell centres at multiples of 45 deg (through cell corners, along grid lines).
// Memory: 8 bytes per entry (uint16 key, uint16 cx, cy; one sentinel per lane) and 4 per block of the per-lane
// index, per heading; entries per heading ~2.3 x the boundary cells facing it. Intel map 888 x 848, T = 64, blocks
// of 32 cells: 1.65 M entries, 22.4 MiB (T = 128: 44 MiB); the board's room 160 x 120 (bench_mcl_main.cpp), T = 32,
// blocks of 64 cells: 39 k entries, 412 KB (T = 16: 221 KB; T = 64: 796 KB).
// Cost: the lanes crossed (2.8 per ray on the Intel map at T = 64 in bench_sensor_models, 4 on the room at T = 32),
// in each a block lookup and a few key steps (0.04 per ray), and 1.4 exact slab tests per ray; on the Intel map
// ~370 x86 instructions per cast in the beam model (callgrind, 2026-12-06), the start's cell found once per
// particle (origin(), cast_from()). Measured: bench_sensor_models (host) and bench_mcl.<board> (README, "Benchmarks" and
// "Budgets on the board"): faster than the distance-transform caster in the cluttered Intel map, not in the board's
// open room, where that caster jumps across the free space in a few steps.
// Build: T passes over the grid plus a heap sort per lane (no heap memory); meant for start-up or the host (Intel
// map: ~0.5 s at T = 64). Every loop is bounded: lanes crossed <= the lane count + 2, key steps and candidates <=
// the lane's entries (a sentinel ends each lane).
#include <cstdint>

#include "est/map/occupancy_grid.hpp"
#include "est/map/ray_casting.hpp"
#include "est/math/fmath.hpp"

namespace est {

inline constexpr std::int32_t kLaneKeyUnitsPerCell = 16;

// One candidate of a lane: the cell and its key; every lane ends with a sentinel of key kLaneSentinel.
struct LaneEntry {
  std::uint16_t key;  // 16 x the smallest u of the cell's square, floored (and one unit less)
  std::uint16_t cx;
  std::uint16_t cy;
  std::uint16_t unused;
};
inline constexpr std::uint16_t kLaneSentinel = 65535;

inline float lane_min(float a, float b) { return a < b ? a : b; }
inline float lane_max(float a, float b) { return a > b ? a : b; }

enum class LaneRayCasterStatus : std::uint8_t {
  ok = 0,
  bad_grid,      // empty or invalid grid, or W + H >= 4000 cells (the uint16 keys)
  bad_bins,      // T is not a power of two in [4, the storage's T]
  too_many_lanes,
  too_many_entries,  // also: one lane of more than 65535 entries
  too_many_blocks,
  bad_block,         // the block is not a power of two in [4, 1024] cells
};

// Read-only view over a built structure.
class LaneRayCaster {
 public:
  struct Tables {
    const float* cos_b = nullptr;        // [T] cos of heading b
    const float* sin_b = nullptr;        // [T]
    const float* u_off = nullptr;        // [T] offsets making u, s >= 0 on the map
    const float* s_off = nullptr;        // [T]
    const std::uint32_t* lane_base = nullptr;  // [T + 1] first lane of heading b in lane_begin
    const LaneEntry* entry = nullptr;           // lanes after lanes, each sorted by key and ended by a sentinel
    const std::uint32_t* block_base = nullptr;  // [T] first block of heading b
    const std::uint32_t* blocks_per_lane = nullptr;  // [T]
    const std::uint32_t* block = nullptr;  // per lane and block of u: the lane's first entry with key >= the block's
    std::uint32_t block_shift = 0;         // a block is 2^block_shift key units
    std::int32_t bins = 0;
    float min_cos_gap = 1.0f;  // cos of 0.7 bin: a heading further from the ray's is replaced by the ray's own
  };

  LaneRayCaster() = default;
  LaneRayCaster(const OccupancyGrid& grid, const Tables& t)
      : grid_(grid), t_(t), mask_(static_cast<std::uint32_t>(t.bins - 1)),
        bins_per_rad_(static_cast<float>(t.bins) / kTwoPi) {}

  bool valid() const { return grid_.valid() && t_.bins > 0 && t_.entry != nullptr; }
  const OccupancyGrid& grid() const { return grid_; }
  std::int32_t bins() const { return t_.bins; }
  float bins_per_rad() const { return bins_per_rad_; }

  // The caster interface of GridRayCaster ((dx, dy) a unit vector): one atan2 to pick the heading.
  float cast(float x, float y, float dx, float dy, float max_range) const {
    if (!fmath::isfinite(dx) || !fmath::isfinite(dy)) return 0.0f;
    return cast_bins(x, y, dx, dy, fmath::atan2(dy, dx) * bins_per_rad_, max_range);
  }

  // heading_bins: the ray's heading in bins (heading * bins_per_rad()), any value within +-2^20; (dx, dy) its unit
  // vector. Exact whatever the heading given, fastest when it is the ray's (the lanes crossed grow with the gap).
  float cast_bins(float x, float y, float dx, float dy, float heading_bins, float max_range) const {
    return cast_from(origin(x, y), dx, dy, heading_bins, max_range);
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

  // cast_bins() from a prepared origin: the same float.
  float cast_from(const Origin& o, float dx, float dy, float heading_bins, float max_range) const {
    if (!o.walk) return 0.0f;
    detail::GridRay r = o.ray;
    if (!r.aim(grid_, dx, dy, max_range)) return 0.0f;
    const float f = heading_bins + 0.5f + 1048576.0f;
    std::uint32_t b = (f >= 0.0f && f < 2097152.0f) ? static_cast<std::uint32_t>(f) & mask_ : 0u;
    float cb = t_.cos_b[b], sb = t_.sin_b[b];
    float cd = cb * dx + sb * dy;  // cos of the gap to the table heading
    if (!(cd >= t_.min_cos_gap)) {  // a heading further than the stored cells allow: take the ray's own
      const float g = fmath::atan2(dy, dx) * bins_per_rad_ + 0.5f + 1048576.0f;
      b = static_cast<std::uint32_t>(g) & mask_;
      cb = t_.cos_b[b];
      sb = t_.sin_b[b];
      cd = cb * dx + sb * dy;
    }
    const float sd = cb * dy - sb * dx;  // sin of the gap: lanes drift by sd per cell along the ray
    const float u0 = cb * r.gx + sb * r.gy - t_.u_off[b];
    const float s0 = cb * r.gy - sb * r.gx - t_.s_off[b];
    const std::uint32_t lane0 = t_.lane_base[b];  // lanes of heading b: [lane_base[b], lane_base[b + 1])
    const std::int32_t lanes = static_cast<std::int32_t>(t_.lane_base[b + 1] - lane0);
    const std::uint32_t block0 = t_.block_base[b];
    const std::uint32_t n_blocks = t_.blocks_per_lane[b];
    // Where the ray leaves the map bounds the walk through the lanes.
    const float fw = static_cast<float>(grid_.width()), fh = static_cast<float>(grid_.height());
    float t_end = r.t_max;
    if (r.step_x != 0) t_end = lane_min(t_end, ((r.step_x > 0 ? fw : 0.0f) - r.gx) * r.inv_dx);
    if (r.step_y != 0) t_end = lane_min(t_end, ((r.step_y > 0 ? fh : 0.0f) - r.gy) * r.inv_dy);
    // The ray drifts across lanes by sd per cell along it: the lane edge it crosses next and the step to the next.
    std::int32_t j = static_cast<std::int32_t>(s0);
    if (j < 0) j = 0;
    if (j >= lanes) j = lanes - 1;
    std::int32_t dj = 0;
    float inv_sd = 0.0f;
    if (sd > 1e-7f || sd < -1e-7f) {
      inv_sd = 1.0f / sd;
      dj = sd > 0.0f ? 1 : -1;
    }
    std::int32_t edge = dj > 0 ? j + 1 : j;
    const std::uint32_t* row = t_.block + block0 + static_cast<std::uint32_t>(j) * n_blocks;
    const std::int32_t row_step = dj * static_cast<std::int32_t>(n_blocks);
    const std::uint32_t last_block = n_blocks - 1u;
    float best = detail::GridRay::kNever;
    const float kU = static_cast<float>(kLaneKeyUnitsPerCell);
    // Key units at t: (u0 + t cd) 16; the first candidate of a lane is 1.5 cells (a square's extent) + 1 unit back.
    const float k0 = u0 * kU, kd = cd * kU;
    float ka = k0 - (1.5f * kU + 1.0f);
    for (std::int32_t n = 0; n < lanes + 2; ++n) {
      float tb = t_end;
      if (dj != 0) {
        const float tl = (static_cast<float>(edge) - s0) * inv_sd;
        if (tl < tb) tb = tl;
      }
      // u <= W + H < 4000 cells on the map (build() refuses larger maps), t <= t_end: key_lo and key_hi stay below
      // 64 000, and the sentinel (65 535) ends both scans.
      const std::int32_t key_lo = ka > 0.0f ? static_cast<std::int32_t>(ka) : 0;
      std::uint32_t blk = static_cast<std::uint32_t>(key_lo) >> t_.block_shift;
      if (blk > last_block) blk = last_block;
      const LaneEntry* e = t_.entry + row[blk];
      // Bounded by the lane's sentinel, whose key is above every key_lo and key_hi (keys < 64 000).
      while (static_cast<std::int32_t>(e->key) < key_lo) ++e;
      float t_lim = tb < best ? tb : best;
      std::int32_t key_hi = static_cast<std::int32_t>(k0 + t_lim * kd) + 1;
      for (; static_cast<std::int32_t>(e->key) <= key_hi; ++e) {
        const float te = enter(r, *e);
        if (te < t_lim) {
          best = te;
          t_lim = te;
          key_hi = static_cast<std::int32_t>(k0 + t_lim * kd) + 1;
        } else if (te < best) {
          best = te;  // entered beyond this lane's segment: a bound for the next lanes
        }
      }
      if (best <= tb || !(tb < t_end)) break;
      j += dj;
      if (j < 0 || j >= lanes) break;
      edge += dj;
      row += row_step;
      ka = k0 + tb * kd - (1.5f * kU + 1.0f);
    }
    if (!(best < r.t_max)) return max_range;
    return detail::cells_to_range(best > 0.0f ? best : 0.0f, grid_.resolution(), max_range);
  }

 private:
  // The ray parameter (cells) at which the traversal enters the cell, or kNever if it does not.
  static float enter(const detail::GridRay& r, const LaneEntry& e) {
    const std::int32_t cx = e.cx;
    const std::int32_t cy = e.cy;
    float txn = -detail::GridRay::kNever, txf = detail::GridRay::kNever;
    float tyn = -detail::GridRay::kNever, tyf = detail::GridRay::kNever;
    if (r.step_x > 0) {
      txn = (static_cast<float>(cx) - r.gx) * r.inv_dx;
      txf = (static_cast<float>(cx + 1) - r.gx) * r.inv_dx;
    } else if (r.step_x < 0) {
      txn = (static_cast<float>(cx + 1) - r.gx) * r.inv_dx;
      txf = (static_cast<float>(cx) - r.gx) * r.inv_dx;
    } else if (cx != r.ix) {
      return detail::GridRay::kNever;
    }
    if (r.step_y > 0) {
      tyn = (static_cast<float>(cy) - r.gy) * r.inv_dy;
      tyf = (static_cast<float>(cy + 1) - r.gy) * r.inv_dy;
    } else if (r.step_y < 0) {
      tyn = (static_cast<float>(cy + 1) - r.gy) * r.inv_dy;
      tyf = (static_cast<float>(cy) - r.gy) * r.inv_dy;
    } else if (cy != r.iy) {
      return detail::GridRay::kNever;
    }
    const float te = txn > tyn ? txn : tyn;
    const float tx = txf < tyf ? txf : tyf;
    if (!(tx > 0.0f)) return detail::GridRay::kNever;
    // Through a corner the traversal takes the y step first: it enters the cell across y, never across x.
    if (te < tx || (te == tx && tyn > txn)) return te;
    return detail::GridRay::kNever;
  }

  OccupancyGrid grid_{};
  Tables t_{};
  std::uint32_t mask_ = 0;
  float bins_per_rad_ = 0.0f;
};

// Runtime-capacity interface over caller-owned arrays.
class LaneRayCasterBuffer {
 public:
  LaneRayCasterBuffer(const LaneRayCasterBuffer&) = delete;
  LaneRayCasterBuffer& operator=(const LaneRayCasterBuffer&) = delete;

  std::uint32_t entries() const { return entries_; }
  std::uint32_t lanes() const { return lanes_; }
  std::uint32_t blocks() const { return blocks_; }
  // Bytes in use by the query: 8 per entry (a sentinel per lane included), 4 per block, 28 per heading (the
  // storage adds 4 per lane of build scratch).
  std::uint32_t bytes_used() const { return 8u * entries_ + 4u * blocks_ + 28u * static_cast<std::uint32_t>(bins_) + 4u; }

  // Builds the lanes of T headings 2 pi b / T for `grid`. Nothing usable is left unless the result is ok (view()
  // is invalid then). Bounded: T passes over the cells, each cell in at most 3 lanes; a heap sort per lane.
  // block_cells: the block index's step along u (a power of two in [4, 1024] cells): 2 bytes per lane and block.
  LaneRayCasterStatus build(const OccupancyGrid& grid, std::int32_t bins, std::int32_t block_cells = 32) {
    view_ = LaneRayCaster{};
    entries_ = lanes_ = blocks_ = 0;
    bins_ = 0;
    if (!grid.valid() || grid.width() > 65535 || grid.height() > 65535) return LaneRayCasterStatus::bad_grid;
    const float fw = static_cast<float>(grid.width()), fh = static_cast<float>(grid.height());
    if (fw + fh >= 4000.0f) return LaneRayCasterStatus::bad_grid;  // u <= W + H: 16 u must fit the uint16 key
    if (bins < 4 || bins > cap_bins_ || (bins & (bins - 1)) != 0) return LaneRayCasterStatus::bad_bins;
    if (block_cells < 4 || block_cells > 1024 || (block_cells & (block_cells - 1)) != 0)
      return LaneRayCasterStatus::bad_block;
    std::uint32_t shift = 4;  // 16 key units per cell
    while ((1 << (shift - 4u)) < block_cells) ++shift;
    std::uint32_t lane = 0, entry = 0, block = 0;
    for (std::int32_t b = 0; b < bins; ++b) {
      const float a = kTwoPi * static_cast<float>(b) / static_cast<float>(bins);
      float s = 0.0f, c = 0.0f;
      fmath::sincos(a, s, c);
      cos_[b] = c;
      sin_[b] = s;
      u_off_[b] = lane_min(lane_min(0.0f, c * fw), lane_min(s * fh, c * fw + s * fh));
      s_off_[b] = lane_min(lane_min(0.0f, -s * fw), lane_min(c * fh, c * fh - s * fw));
      const float s_span = lane_max(lane_max(0.0f, -s * fw), lane_max(c * fh, c * fh - s * fw)) - s_off_[b];
      const std::uint32_t n_lanes = static_cast<std::uint32_t>(s_span) + 2u;
      const float u_span = lane_max(lane_max(0.0f, c * fw), lane_max(s * fh, c * fw + s * fh)) - u_off_[b];
      const std::uint32_t n_blocks = static_cast<std::uint32_t>(u_span) / static_cast<std::uint32_t>(block_cells) + 2u;
      block_base_[b] = block;
      blocks_per_lane_[b] = n_blocks;
      if (static_cast<std::uint64_t>(block) + static_cast<std::uint64_t>(n_lanes) * n_blocks > cap_blocks_)
        return LaneRayCasterStatus::too_many_blocks;
      lane_base_[b] = lane;
      if (lane + n_lanes + 1u > cap_lanes_) return LaneRayCasterStatus::too_many_lanes;
      // The sides a ray of this heading (+- 3/4 bin) can enter a cell from.
      const float half = 0.75f * kTwoPi / static_cast<float>(bins);
      float s_lo = 0.0f, c_lo = 0.0f, s_hi = 0.0f, c_hi = 0.0f;
      fmath::sincos(a - half, s_lo, c_lo);
      fmath::sincos(a + half, s_hi, c_hi);
      const Faces faces{c_lo > 0.0f || c_hi > 0.0f, c_lo < 0.0f || c_hi < 0.0f, s_lo > 0.0f || s_hi > 0.0f,
                        s_lo < 0.0f || s_hi < 0.0f};
      std::uint32_t* begin = lane_begin_ + lane;  // scratch: the lanes' first entries
      begin[0] = 0;
      for (std::uint32_t k = 1; k <= n_lanes; ++k) begin[k] = 1;  // each lane's sentinel
      // Pass 1: count per lane (into begin[j + 1]); pass 2: place; then sort each lane by key.
      for (int pass = 0; pass < 2; ++pass) {
        for (std::int32_t cy = 0; cy < grid.height(); ++cy) {
          for (std::int32_t cx = 0; cx < grid.width(); ++cx) {
            if (!enterable(grid, cx, cy, faces)) continue;
            std::uint32_t j0 = 0, j1 = 0;
            std::uint16_t key = 0;
            lanes_of(cx, cy, c, s, u_off_[b], s_off_[b], n_lanes, j0, j1, key);
            for (std::uint32_t j = j0; j <= j1; ++j) {
              if (pass == 0) {
                ++begin[j + 1];
              } else {
                ent_[entry + begin[j]++] =
                    LaneEntry{key, static_cast<std::uint16_t>(cx), static_cast<std::uint16_t>(cy), 0};
              }
            }
          }
        }
        if (pass == 0) {
          for (std::uint32_t k = 0; k < n_lanes; ++k) begin[k + 1] += begin[k];
          if (entry + begin[n_lanes] > cap_entries_) return LaneRayCasterStatus::too_many_entries;
        }
      }
      // After placing, begin[j] is lane j's sentinel: write it, shift back and make the offsets absolute.
      for (std::uint32_t k = 0; k < n_lanes; ++k) ent_[entry + begin[k]] = LaneEntry{kLaneSentinel, 0, 0, 0};
      for (std::uint32_t k = n_lanes; k > 0; --k) begin[k] = begin[k - 1] + 1u + entry;
      begin[0] = entry;
      for (std::uint32_t k = 0; k < n_lanes; ++k) {
        const std::uint32_t last = begin[k + 1] - 1u;  // the sentinel
        heap_sort(begin[k], last);
        std::uint32_t i = begin[k];
        for (std::uint32_t q = 0; q < n_blocks; ++q) {
          const std::uint32_t first_key = q << shift;
          while (i < last && ent_[i].key < first_key) ++i;
          block_[block + k * n_blocks + q] = i;
        }
      }
      block += n_lanes * n_blocks;
      entry = begin[n_lanes];
      lane += n_lanes;
    }
    lane_base_[bins] = lane;
    lane_begin_[lane] = entry;
    entries_ = entry;
    lanes_ = lane;
    blocks_ = block;
    bins_ = bins;
    LaneRayCaster::Tables t;
    t.cos_b = cos_;
    t.sin_b = sin_;
    t.u_off = u_off_;
    t.s_off = s_off_;
    t.lane_base = lane_base_;
    t.entry = ent_;
    t.block_base = block_base_;
    t.blocks_per_lane = blocks_per_lane_;
    t.block = block_;
    t.block_shift = shift;
    t.bins = bins;
    float sg = 0.0f, cg = 1.0f;
    fmath::sincos(0.7f * kTwoPi / static_cast<float>(bins), sg, cg);
    t.min_cos_gap = cg;
    view_ = LaneRayCaster(grid, t);
    return LaneRayCasterStatus::ok;
  }
  LaneRayCaster view() const { return view_; }

 protected:
  LaneRayCasterBuffer(float* cos_b, float* sin_b, float* u_off, float* s_off, std::uint32_t* lane_base,
                      std::int32_t cap_bins, std::uint32_t* lane_begin, std::uint32_t cap_lanes, LaneEntry* entries,
                      std::uint32_t cap_entries, std::uint32_t* block_base, std::uint32_t* blocks_per_lane,
                      std::uint32_t* block, std::uint32_t cap_blocks)
      : cos_(cos_b), sin_(sin_b), u_off_(u_off), s_off_(s_off), lane_base_(lane_base), cap_bins_(cap_bins),
        lane_begin_(lane_begin), cap_lanes_(cap_lanes), ent_(entries), cap_entries_(cap_entries),
        block_base_(block_base), blocks_per_lane_(blocks_per_lane), block_(block), cap_blocks_(cap_blocks) {}
  ~LaneRayCasterBuffer() = default;

 private:
  struct Faces {
    bool from_left, from_right, from_below, from_above;  // rays with dx > 0, dx < 0, dy > 0, dy < 0
  };
  static bool open(const OccupancyGrid& g, std::int32_t cx, std::int32_t cy) {
    return g.contains(cx, cy) && !g.is_occupied_value(g.at(cx, cy));
  }
  static bool enterable(const OccupancyGrid& g, std::int32_t cx, std::int32_t cy, const Faces& f) {
    if (!g.is_occupied_value(g.at(cx, cy))) return false;
    return (f.from_left && open(g, cx - 1, cy)) || (f.from_right && open(g, cx + 1, cy)) ||
           (f.from_below && open(g, cx, cy - 1)) || (f.from_above && open(g, cx, cy + 1));
  }
  // The lanes [j0, j1] the cell's square overlaps (widened by 1/64 cell) and its key.
  static void lanes_of(std::int32_t cx, std::int32_t cy, float c, float s, float u_off, float s_off,
                       std::uint32_t n_lanes, std::uint32_t& j0, std::uint32_t& j1, std::uint16_t& key) {
    float umin = 3.0e38f, smin = 3.0e38f, smax = -3.0e38f;
    for (int k = 0; k < 4; ++k) {
      const float x = static_cast<float>(cx + (k & 1));
      const float y = static_cast<float>(cy + (k >> 1));
      const float u = c * x + s * y - u_off;
      const float sl = c * y - s * x - s_off;
      umin = lane_min(umin, u);
      smin = lane_min(smin, sl);
      smax = lane_max(smax, sl);
    }
    const float lo = smin - 1.0f / 64.0f, hi = smax + 1.0f / 64.0f;
    j0 = lo > 0.0f ? static_cast<std::uint32_t>(lo) : 0u;
    j1 = hi > 0.0f ? static_cast<std::uint32_t>(hi) : 0u;
    if (j1 >= n_lanes) j1 = n_lanes - 1;
    if (j0 > j1) j0 = j1;
    const float k16 = umin * static_cast<float>(kLaneKeyUnitsPerCell) - 1.0f;  // floor, one unit of slack
    key = k16 > 0.0f ? static_cast<std::uint16_t>(k16) : std::uint16_t{0};
  }
  void swap_at(std::uint32_t a, std::uint32_t b) {
    const LaneEntry e = ent_[a];
    ent_[a] = ent_[b];
    ent_[b] = e;
  }
  void sift_down(std::uint32_t base, std::uint32_t root, std::uint32_t n) {
    for (std::uint32_t guard = 0; guard < 32u; ++guard) {
      std::uint32_t child = 2u * root + 1u;
      if (child >= n) return;
      if (child + 1u < n && ent_[base + child + 1u].key > ent_[base + child].key) ++child;
      if (ent_[base + root].key >= ent_[base + child].key) return;
      swap_at(base + root, base + child);
      root = child;
    }
  }
  // Sorts [lo, hi) by key (ties in any order: the query tests every candidate up to its bound).
  void heap_sort(std::uint32_t lo, std::uint32_t hi) {
    const std::uint32_t n = hi - lo;
    if (n < 2u) return;
    for (std::uint32_t i = n / 2u; i-- > 0u;) sift_down(lo, i, n);
    for (std::uint32_t end = n - 1u; end > 0u; --end) {
      swap_at(lo, lo + end);
      sift_down(lo, 0u, end);
    }
  }

  float* cos_;
  float* sin_;
  float* u_off_;
  float* s_off_;
  std::uint32_t* lane_base_;
  std::int32_t cap_bins_;
  std::uint32_t* lane_begin_;
  std::uint32_t cap_lanes_;
  LaneEntry* ent_;
  std::uint32_t cap_entries_;
  std::uint32_t* block_base_;
  std::uint32_t* blocks_per_lane_;
  std::uint32_t* block_;
  std::uint32_t cap_blocks_;
  std::uint32_t entries_ = 0, lanes_ = 0, blocks_ = 0;
  std::int32_t bins_ = 0;
  LaneRayCaster view_{};
};

// The owner: T headings, at most MaxLanes lanes, MaxEntries entries and MaxBlocks blocks over all headings; a
// static object. Lanes per heading <= |W sin| + |H cos| + 2, blocks per lane <= (|W cos| + |H sin|) / block + 2;
// entries are what the map needs (build() says which capacity is short).
template <std::int32_t TMax, std::uint32_t MaxLanes, std::uint32_t MaxEntries, std::uint32_t MaxBlocks>
class LaneRayCasterStorage final : public LaneRayCasterBuffer {
  static_assert(TMax >= 4 && TMax <= 65536 && (TMax & (TMax - 1)) == 0, "T must be a power of two >= 4");
  static_assert(MaxLanes > 0 && MaxEntries > 0 && MaxBlocks > 0, "capacities must be positive");

 public:
  static constexpr std::uint64_t kBytes =
      8ull * MaxEntries + 4ull * (MaxLanes + 1ull) + 4ull * MaxBlocks + 28ull * TMax + 4ull;
  LaneRayCasterStorage()
      : LaneRayCasterBuffer(cos_, sin_, u_off_, s_off_, lane_base_, TMax, lane_begin_, MaxLanes + 1u, entry_storage_,
                            MaxEntries, block_base_, blocks_per_lane_, block_, MaxBlocks) {}

 private:
  static constexpr std::uint32_t kT = static_cast<std::uint32_t>(TMax);
  float cos_[kT];
  float sin_[kT];
  float u_off_[kT];
  float s_off_[kT];
  std::uint32_t lane_base_[kT + 1u];
  std::uint32_t lane_begin_[MaxLanes + 1u];
  LaneEntry entry_storage_[MaxEntries];
  std::uint32_t block_base_[kT];
  std::uint32_t blocks_per_lane_[kT];
  std::uint32_t block_[MaxBlocks];
};

}  // namespace est
