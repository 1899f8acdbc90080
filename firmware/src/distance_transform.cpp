// Exact Euclidean distance transform, Meijster et al. 2000 / Felzenszwalb-Huttenlocher 2012, in integers.
#include "est/map/distance_transform.hpp"

namespace est {
namespace {

// floor(a / b) for b > 0 (C++ division truncates toward zero).
std::int32_t floor_div(std::int32_t a, std::int32_t b) {
  const std::int32_t q = a / b;
  return (a % b != 0 && a < 0) ? q - 1 : q;
}

// floor(sqrt(n)), exact, 16 iterations.
std::uint32_t isqrt(std::uint32_t n) {
  std::uint32_t root = 0;
  std::uint32_t bit = 1u << 30;
  for (int i = 0; i < 16; ++i) {
    if (n >= root + bit) {
      n -= root + bit;
      root = (root >> 1) + bit;
    } else {
      root >>= 1;
    }
    bit >>= 2;
  }
  return root;
}

}  // namespace

MapStatus DistanceTransformBuffer::build(const OccupancyGrid& grid) {
  if (!grid.valid()) return MapStatus::empty;
  const std::int32_t W = grid.width();
  const std::int32_t H = grid.height();
  if (W > cap_w_ || H > cap_h_) return MapStatus::too_large;
  width_ = W;
  height_ = H;
  resolution_ = grid.resolution();

  // "No obstacle in this column": larger than any real distance, and its square fits int32 (W, H <= 16384).
  const std::int32_t inf = W + H;
  const std::int32_t inf2 = inf * inf;
  const std::uint8_t* cells = grid.cells();

  // Pass 1, per column: distance along y to the nearest occupied cell (kept in q_ until pass 2 reads it).
  for (std::int32_t x = 0; x < W; ++x) {
    std::int32_t g = grid.is_occupied_value(cells[x]) ? 0 : inf;
    q_[x] = static_cast<std::uint16_t>(g);
    for (std::int32_t y = 1; y < H; ++y) {
      const std::int32_t i = y * W + x;
      g = grid.is_occupied_value(cells[i]) ? 0 : (g < inf ? g + 1 : inf);
      q_[i] = static_cast<std::uint16_t>(g);
    }
    for (std::int32_t y = H - 2; y >= 0; --y) {
      const std::int32_t i = y * W + x;
      const std::int32_t below = q_[i + W];
      if (below + 1 < q_[i]) q_[i] = static_cast<std::uint16_t>(below + 1);
    }
  }

  // Pass 2, per row: lower envelope of the parabolas (x - i)^2 + g(i)^2; s_ holds their apexes i, t_ the first x
  // where each one is lowest.
  for (std::int32_t y = 0; y < H; ++y) {
    std::uint16_t* row = q_ + y * W;
    for (std::int32_t x = 0; x < W; ++x) {
      const std::int32_t g = row[x];
      f_[x] = g * g;
    }
    std::int32_t k = 0;
    s_[0] = 0;
    t_[0] = 0;
    for (std::int32_t u = 1; u < W; ++u) {
      // Pops are bounded: each u is pushed once, so at most W pops per row in total.
      while (k >= 0) {
        const std::int32_t a = t_[k] - s_[k];
        const std::int32_t b = t_[k] - u;
        if (a * a + f_[s_[k]] <= b * b + f_[u]) break;
        --k;
      }
      if (k < 0) {
        k = 0;
        s_[0] = u;
        t_[0] = 0;
      } else {
        const std::int32_t i = s_[k];
        const std::int32_t w = 1 + floor_div(u * u - i * i + f_[u] - f_[i], 2 * (u - i));
        if (w < W) {
          ++k;
          s_[k] = u;
          t_[k] = w;
        }
      }
    }
    for (std::int32_t u = W - 1; u >= 0; --u) {
      const std::int32_t a = u - s_[k];
      const std::int32_t d2 = a * a + f_[s_[k]];
      std::uint16_t q = kDistanceSaturated;
      if (d2 < inf2 && d2 < 4096 * 4096) {
        q = static_cast<std::uint16_t>(isqrt(256u * static_cast<std::uint32_t>(d2)));
        if (q > kDistanceSaturated - 1u) q = kDistanceSaturated - 1u;
      }
      row[u] = q;
      if (u == t_[k] && k > 0) --k;
    }
  }
  return MapStatus::ok;
}

}  // namespace est
