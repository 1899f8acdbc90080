#pragma once
// The likelihood field of Thrun table 6.3 evaluated for a whole particle set at once, bit-identical to
// likelihood_field_range_finder_model() for every particle.
//
// Speed without changing a bit: (1) the quantized per-beam term (uint16 steps below the largest term, see
// likelihood_field_range_finder_model.hpp), which depends on the end point's cell only, is stored per cell of the map
// padded by one cell on every side: one load, and the bounds check is a clamp of each index to the pad (no branch);
// (2) the terms are summed as integers, exact in any order; (3) particles outside, beams inside: a particle's frame
// stays in registers while its beams' end points (precomputed per scan in cell units, up to kLikelihoodFieldChunk
// at a time) are rotated onto the grid. Per particle-beam: 8 flops, 2 conversions, 2 clamps, 1 load, 1 add.
// Memory: 2 bytes per cell of (W + 2) x (H + 2) (Intel map 888 x 848: 1.44 MiB; a 200 x 200 board map 80 KiB) on top
// of the distance transform it is built from; or the scalar model with its 2 KiB table.
#include <cstdint>
#include <cstring>

#include "est/geometry/pose2.hpp"
#include "est/map/occupancy_grid.hpp"
#include "est/math/fmath.hpp"
#include "est/math/lanes.hpp"
#include "est/sensor/likelihood_field_range_finder_model.hpp"
#include "est/sensor/range_scan.hpp"

namespace est {

// Read-only view: the quantized term per cell of the padded map ((width + 2) x (height + 2), row-major); the origin
// and resolution are the map's.
class LikelihoodFieldGrid {
 public:
  LikelihoodFieldGrid() = default;
  LikelihoodFieldGrid(const std::uint16_t* cells, std::int32_t width, std::int32_t height, float origin_x,
                      float origin_y, float inv_resolution, float log_peak)
      : cells_(cells),
        w_(width),
        h_(height),
        ox_(origin_x),
        oy_(origin_y),
        inv_res_(inv_resolution),
        log_peak_(log_peak) {}
  bool valid() const { return cells_ != nullptr && w_ > 0 && h_ > 0; }
  const std::uint16_t* cells() const { return cells_; }
  std::int32_t width() const { return w_; }
  std::int32_t height() const { return h_; }
  std::uint32_t stride() const { return static_cast<std::uint32_t>(w_) + 2u; }  // padded row length
  std::uint32_t rows() const { return static_cast<std::uint32_t>(h_) + 2u; }
  float origin_x() const { return ox_; }
  float origin_y() const { return oy_; }
  float inv_resolution() const { return inv_res_; }
  float log_peak() const { return log_peak_; }

 private:
  const std::uint16_t* cells_ = nullptr;
  std::int32_t w_ = 0, h_ = 0;
  float ox_ = 0.0f, oy_ = 0.0f, inv_res_ = 1.0f, log_peak_ = 0.0f;
};

class LikelihoodFieldGridBuffer {
 public:
  LikelihoodFieldGridBuffer(const LikelihoodFieldGridBuffer&) = delete;
  LikelihoodFieldGridBuffer& operator=(const LikelihoodFieldGridBuffer&) = delete;

  // Tabulates a configured field over `grid` (the grid it was configured with), the one-cell pad included.
  MapStatus build(const LikelihoodField& field, const OccupancyGrid& grid) {
    if (!field.ready() || !grid.valid()) return MapStatus::empty;
    if (grid.width() > cap_w_ || grid.height() > cap_h_) return MapStatus::too_large;
    const std::int32_t stride = grid.width() + 2, rows = grid.height() + 2;
    for (std::int32_t iy = 0; iy < rows; ++iy)
      for (std::int32_t ix = 0; ix < stride; ++ix) cells_[iy * stride + ix] = field.steps_at_cell(ix, iy);
    view_ = LikelihoodFieldGrid(cells_, grid.width(), grid.height(), grid.origin_x(), grid.origin_y(),
                                grid.inv_resolution(), field.log_term_max());
    return MapStatus::ok;
  }
  LikelihoodFieldGrid view() const { return view_; }
  // Cells a buffer needs for a map of w x h (the one-cell pad included).
  static constexpr std::uint32_t cells_for(std::int32_t w, std::int32_t h) {
    return (static_cast<std::uint32_t>(w) + 2u) * (static_cast<std::uint32_t>(h) + 2u);
  }

 protected:
  LikelihoodFieldGridBuffer(std::uint16_t* cells, std::int32_t cap_w, std::int32_t cap_h)
      : cells_(cells), cap_w_(cap_w), cap_h_(cap_h) {}
  ~LikelihoodFieldGridBuffer() = default;

 private:
  std::uint16_t* cells_;
  std::int32_t cap_w_, cap_h_;
  LikelihoodFieldGrid view_{};
};

template <std::int32_t WMax, std::int32_t HMax>
class LikelihoodFieldGridStorage final : public LikelihoodFieldGridBuffer {
  static_assert(WMax > 0 && HMax > 0 && WMax <= 16384 && HMax <= 16384, "sides are limited to 16384 cells");

 public:
  static constexpr std::uint32_t kBytes =
      2u * (static_cast<std::uint32_t>(WMax) + 2u) * (static_cast<std::uint32_t>(HMax) + 2u);
  LikelihoodFieldGridStorage() : LikelihoodFieldGridBuffer(cells_, WMax, HMax) {}

 private:
  std::uint16_t cells_[(static_cast<std::uint32_t>(WMax) + 2u) * (static_cast<std::uint32_t>(HMax) + 2u)];
};

// Beams (non-max) whose end points one pass over the particles takes (2 floats each on the stack). On a board (no
// data cache) each particle's frame stays in registers over up to 128 beams; on a host, blocks of
// kLikelihoodFieldBlock particles sweep 16 beams at a time, so the cells the block's end points touch stay in L1.
// The sums are integers: the same bits in either order.
#if defined(__arm__)
inline constexpr std::int32_t kLikelihoodFieldChunk = 128;
#else
inline constexpr std::int32_t kLikelihoodFieldChunk = 16;
inline constexpr std::uint32_t kLikelihoodFieldBlock = 256;
#endif

namespace detail {

inline std::uint32_t likelihood_field_step(float px, float py, float c, float s, float bx, float by,
                                           const std::uint16_t* __restrict cells, std::uint32_t stride,
                                           std::uint32_t rows) {
  const float gx = px + (c * bx - s * by);
  const float gy = py + (s * bx + c * by);
  std::uint32_t ix = static_cast<std::uint32_t>(static_cast<std::int32_t>(gx));
  std::uint32_t iy = static_cast<std::uint32_t>(static_cast<std::int32_t>(gy));
  ix = ix < stride ? ix : 0u;  // below 0 or beyond the pad: the pad
  iy = iy < rows ? iy : 0u;
  return cells[iy * stride + ix];
}

// The summed steps of m beams (end points `off`, interleaved x, y in cell units) from one particle's sensor frame
// (px, py in padded cell units, rotation c, s): the scalar model's arithmetic, each index clamped to the pad.
inline std::uint32_t likelihood_field_sweep(float px, float py, float c, float s, const float* __restrict off,
                                            std::int32_t m, const std::uint16_t* __restrict cells,
                                            std::uint32_t stride, std::uint32_t rows) {
  std::uint32_t sum0 = 0, sum1 = 0;
  const float* const end = off + 2 * (m & ~1);
  for (; off != end; off += 4) {  // two beams a turn: the loop's own instructions halve
    sum0 += likelihood_field_step(px, py, c, s, off[0], off[1], cells, stride, rows);
    sum1 += likelihood_field_step(px, py, c, s, off[2], off[3], cells, stride, rows);
  }
  if ((m & 1) != 0) sum0 += likelihood_field_step(px, py, c, s, off[0], off[1], cells, stride, rows);
  return sum0 + sum1;
}

#if !defined(__arm__)
// The same sum in two loops, for a host: the cell indices of the chunk first (float and integer arithmetic the
// compiler vectorizes), then the loads. Equal to likelihood_field_sweep (the same indices, an integer sum).
inline std::uint32_t likelihood_field_sweep_indexed(float px, float py, float c, float s,
                                                    const float* __restrict off, std::int32_t m,
                                                    const std::uint16_t* __restrict cells, std::uint32_t stride,
                                                    std::uint32_t rows) {
  std::uint32_t idx[kLikelihoodFieldChunk];
  for (std::int32_t k = 0; k < m; ++k) {
    const float bx = off[2 * k], by = off[2 * k + 1];
    const float gx = px + (c * bx - s * by);
    const float gy = py + (s * bx + c * by);
    std::uint32_t ix = static_cast<std::uint32_t>(static_cast<std::int32_t>(gx));
    std::uint32_t iy = static_cast<std::uint32_t>(static_cast<std::int32_t>(gy));
    ix = ix < stride ? ix : 0u;
    iy = iy < rows ? iy : 0u;
    idx[k] = iy * stride + ix;
  }
  std::uint32_t sum = 0;
  for (std::int32_t k = 0; k < m; ++k) sum += cells[idx[k]];
  return sum;
}
#endif

// A particle's sensor frame in padded cell units. sensor_frame() with one sincos instead of two when the mount is not
// rotated: theta + 0 is theta exactly (s + 0 turns the sine of -0 into the +0 that sin(-0 + 0) gives). A particle
// that is not finite gets a frame at 0 (its result is the floor; here it only must not convert NaN to an integer).
struct LikelihoodFieldFrame {
  float px, py, c, s;
};
inline LikelihoodFieldFrame likelihood_field_frame(float x, float y, float th, const Pose2& mount,
                                                   const LikelihoodFieldGrid& g) {
  float s = 0.0f, c = 0.0f;
  fmath::sincos(th, s, c);
  float ss = s + 0.0f, cs = c;
  if (mount.theta != 0.0f) fmath::sincos(th + mount.theta, ss, cs);
  const float fx = x + c * mount.x - s * mount.y;
  const float fy = y + s * mount.x + c * mount.y;
  if (!(fmath::isfinite(x) && fmath::isfinite(y) && fmath::isfinite(th))) return {0.0f, 0.0f, 0.0f, 0.0f};
  const float inv = g.inv_resolution();
  return {lf_cell_coordinate(fx, g.origin_x(), inv), lf_cell_coordinate(fy, g.origin_y(), inv), cs, ss};
}

#if !defined(__arm__)
// likelihood_field_frame for particles [0, m) into the frame arrays, kLanes at a time (lanes::sincos: fmath's bits),
// the few lanes beyond its range (and non-finite particles) through likelihood_field_frame itself: the same bits.
inline void likelihood_field_frames(const float* x, const float* y, const float* th, std::uint32_t m,
                                    const Pose2& mount, const LikelihoodFieldGrid& g, float* fpx, float* fpy,
                                    float* fc, float* fs) {
  using lanes::F;
  using lanes::I;
  constexpr float kLimit = 0x1p24f;
  const float inv = g.inv_resolution(), ox = g.origin_x(), oy = g.origin_y();
  const auto cell = [&](F v, float origin) {  // lf_cell_coordinate
    const F c = (v - origin) * inv + 1.0f;
    const F lo = c > -kLimit ? c : lanes::splat(-kLimit);
    return lo < kLimit ? lo : lanes::splat(kLimit);
  };
  const bool rotated = mount.theta != 0.0f;
  const F zero = {};
  std::uint32_t i = 0;
  for (; i + lanes::kLanes <= m; i += lanes::kLanes) {
    const F vx = lanes::load(x + i), vy = lanes::load(y + i), vt = lanes::load(th + i);
    F s, c;
    I ok = lanes::sincos(vt, s, c);
    F ss = s + 0.0f, cs = c;
    if (rotated) ok &= lanes::sincos(vt + mount.theta, ss, cs);
    const F fx = (vx + c * mount.x) - s * mount.y;
    const F fy = (vy + s * mount.x) + c * mount.y;
    const I finite = ((lanes::bits(vx) & 0x7fffffffu) < 0x7f800000u) &
                     ((lanes::bits(vy) & 0x7fffffffu) < 0x7f800000u) & ((lanes::bits(vt) & 0x7fffffffu) < 0x7f800000u);
    lanes::store(fpx + i, finite ? cell(fx, ox) : zero);
    lanes::store(fpy + i, finite ? cell(fy, oy) : zero);
    lanes::store(fc + i, finite ? cs : zero);
    lanes::store(fs + i, finite ? ss : zero);
    if (lanes::count(ok) == lanes::kLanes) continue;
    for (std::uint32_t j = 0; j < lanes::kLanes; ++j) {
      if (ok[j] != 0) continue;
      const LikelihoodFieldFrame f = likelihood_field_frame(x[i + j], y[i + j], th[i + j], mount, g);
      fpx[i + j] = f.px;
      fpy[i + j] = f.py;
      fc[i + j] = f.c;
      fs[i + j] = f.s;
    }
  }
  for (; i < m; ++i) {
    const LikelihoodFieldFrame f = likelihood_field_frame(x[i], y[i], th[i], mount, g);
    fpx[i] = f.px;
    fpy[i] = f.py;
    fc[i] = f.c;
    fs[i] = f.s;
  }
}
#endif

// The end points of the next up to kLikelihoodFieldChunk beams that are not max readings, from beam k on; k moves
// past them. Returns how many.
inline std::int32_t likelihood_field_offsets(const ScanBeams& z, std::int32_t& k, float inv, float* off) {
  std::int32_t m = 0;
  for (; k < z.count && m < kLikelihoodFieldChunk; ++k) {
    if (z.is_max[k]) continue;
    off[2 * m] = lf_beam_offset(z.range[k], z.ux[k], inv);
    off[2 * m + 1] = lf_beam_offset(z.range[k], z.uy[k], inv);
    ++m;
  }
  return m;
}

}  // namespace detail

// out[i] = likelihood_field_range_finder_model(z, (x[i], y[i], theta[i]), mount, field) for i < n, bit for bit
// (the grid tabulated from `field`). O(n K); per particle one or two sincos (per chunk of beams on a board).
inline void likelihood_field_range_finder_model_batch(const ScanBeams& z, const float* x, const float* y,
                                                      const float* theta, std::uint32_t n, const Pose2& mount,
                                                      const LikelihoodFieldGrid& g, float* out) {
  std::int32_t hits = 0;
  for (std::int32_t k = 0; k < z.count; ++k) hits += z.is_max[k] ? 0 : 1;
  const float floor_all = static_cast<float>(hits) * kBeamLogDensityFloor;
  if (!g.valid() || !mount.is_finite()) {
    for (std::uint32_t i = 0; i < n; ++i) out[i] = floor_all;
    return;
  }
  const float inv = g.inv_resolution(), log_peak = g.log_peak();
  const std::uint16_t* cells = g.cells();
  const std::uint32_t stride = g.stride(), rows = g.rows();
  float off[2 * kLikelihoodFieldChunk];
#if defined(__arm__)
  std::int32_t k = 0;
  bool first = true;
  do {  // bounded: every pass takes up to kLikelihoodFieldChunk beams of z.count
    const std::int32_t m = detail::likelihood_field_offsets(z, k, inv, off);
    for (std::uint32_t i = 0; i < n; ++i) {
      const detail::LikelihoodFieldFrame f = detail::likelihood_field_frame(x[i], y[i], theta[i], mount, g);
      std::uint32_t steps = detail::likelihood_field_sweep(f.px, f.py, f.c, f.s, off, m, cells, stride, rows);
      if (!first) {
        std::uint32_t before = 0;
        std::memcpy(&before, &out[i], sizeof before);  // the running integer sum, kept in out's bits between passes
        steps += before;
      }
      std::memcpy(&out[i], &steps, sizeof steps);
    }
    first = false;
  } while (k < z.count);
  for (std::uint32_t i = 0; i < n; ++i) {
    std::uint32_t steps = 0;
    std::memcpy(&steps, &out[i], sizeof steps);
    const bool finite = fmath::isfinite(x[i]) && fmath::isfinite(y[i]) && fmath::isfinite(theta[i]);
    out[i] = finite ? lf_log_likelihood(hits, log_peak, steps) : floor_all;
  }
#else
  float fpx[kLikelihoodFieldBlock], fpy[kLikelihoodFieldBlock], fc[kLikelihoodFieldBlock], fs[kLikelihoodFieldBlock];
  std::uint32_t acc[kLikelihoodFieldBlock];
  for (std::uint32_t b0 = 0; b0 < n; b0 += kLikelihoodFieldBlock) {
    const std::uint32_t m = n - b0 < kLikelihoodFieldBlock ? n - b0 : kLikelihoodFieldBlock;
    detail::likelihood_field_frames(x + b0, y + b0, theta + b0, m, mount, g, fpx, fpy, fc, fs);
    for (std::uint32_t i = 0; i < m; ++i) acc[i] = 0u;
    std::int32_t k = 0;
    do {  // bounded: every pass takes up to kLikelihoodFieldChunk beams of z.count
      const std::int32_t mk = detail::likelihood_field_offsets(z, k, inv, off);
      for (std::uint32_t i = 0; i < m; ++i)
        acc[i] += detail::likelihood_field_sweep_indexed(fpx[i], fpy[i], fc[i], fs[i], off, mk, cells, stride, rows);
    } while (k < z.count);
    for (std::uint32_t i = 0; i < m; ++i) {
      const bool finite =
          fmath::isfinite(x[b0 + i]) && fmath::isfinite(y[b0 + i]) && fmath::isfinite(theta[b0 + i]);
      out[b0 + i] = finite ? lf_log_likelihood(hits, log_peak, acc[i]) : floor_all;
    }
  }
#endif
}

}  // namespace est
