#pragma once
// Occupancy grid map (Probabilistic Robotics ch. 6.2 and 9): a read-only view, a runtime-capacity buffer and an
// owning storage whose capacity is in the type (ETL style: code that only reads a map takes OccupancyGrid, code
// that fills one takes OccupancyGridBuffer&, and only the owner carries W_max x H_max).
//
// Cells are uint8: occupancy probability in percent, 0 (free) .. 100 (occupied), or kUnknownCell (255), the
// ROS nav_msgs/OccupancyGrid convention with -1 stored as 255. Cell (cx, cy) covers
//   [origin_x + cx * resolution, origin_x + (cx + 1) * resolution) x [origin_y + cy * resolution, ...),
// row-major with cy = 0 at origin_y (the bottom row of a ROS map image). The origin is the world position of
// the corner of cell (0, 0); a rotated origin (ROS yaw != 0) is not supported (the host loader rejects it).
#include <cstdint>

#include "est/math/fmath.hpp"

namespace est {

inline constexpr std::uint8_t kUnknownCell = 255;
inline constexpr std::uint8_t kOccupiedCell = 100;
inline constexpr std::uint8_t kFreeCell = 0;

enum class CellClass : std::uint8_t { free, occupied, unknown };

enum class MapStatus : std::uint8_t {
  ok = 0,
  too_large,        // width x height exceeds the storage's capacity
  empty,            // width or height <= 0
  bad_resolution,   // resolution not finite or <= 0
  bad_origin,       // origin not finite
  bad_thresholds,   // free_max >= occupied_min or occupied_min > 100
  full,             // a fixed-capacity table has no room left
  duplicate,        // an entry with this key already exists
  nonfinite,        // a coordinate or value was NaN or infinite
};

// Classification thresholds in percent: occupied when value >= occupied_min, free when value <= free_max,
// unknown otherwise (and always for kUnknownCell). The defaults are ROS map_server's 0.65 and 0.196.
struct CellThresholds {
  std::uint8_t occupied_min = 65;
  std::uint8_t free_max = 19;
};

class OccupancyGrid {
 public:
  OccupancyGrid() = default;
  OccupancyGrid(const std::uint8_t* cells, std::int32_t width, std::int32_t height, float resolution,
                float origin_x, float origin_y, CellThresholds thresholds = {})
      : cells_(cells),
        width_(width),
        height_(height),
        resolution_(resolution),
        inv_resolution_(1.0f / resolution),
        origin_x_(origin_x),
        origin_y_(origin_y),
        thresholds_(thresholds) {}

  std::int32_t width() const { return width_; }
  std::int32_t height() const { return height_; }
  std::int32_t cell_count() const { return width_ * height_; }
  float resolution() const { return resolution_; }
  float inv_resolution() const { return inv_resolution_; }
  float origin_x() const { return origin_x_; }
  float origin_y() const { return origin_y_; }
  CellThresholds thresholds() const { return thresholds_; }
  const std::uint8_t* cells() const { return cells_; }
  bool valid() const { return cells_ != nullptr && width_ > 0 && height_ > 0; }

  bool contains(std::int32_t cx, std::int32_t cy) const { return cx >= 0 && cy >= 0 && cx < width_ && cy < height_; }
  std::int32_t index(std::int32_t cx, std::int32_t cy) const { return cy * width_ + cx; }
  std::uint8_t at(std::int32_t cx, std::int32_t cy) const { return cells_[index(cx, cy)]; }

  // World (metres) to cell; false (and cx, cy untouched) outside the map or for non-finite input.
  bool world_to_cell(float x, float y, std::int32_t& cx, std::int32_t& cy) const {
    const float gx = (x - origin_x_) * inv_resolution_;
    const float gy = (y - origin_y_) * inv_resolution_;
    if (!(gx >= 0.0f && gy >= 0.0f && gx < static_cast<float>(width_) && gy < static_cast<float>(height_)))
      return false;
    cx = static_cast<std::int32_t>(gx);
    cy = static_cast<std::int32_t>(gy);
    // gx just below width can round up to width in float: keep the index in range.
    if (cx >= width_) cx = width_ - 1;
    if (cy >= height_) cy = height_ - 1;
    return true;
  }
  // Centre of a cell in world coordinates.
  float cell_center_x(std::int32_t cx) const { return origin_x_ + (static_cast<float>(cx) + 0.5f) * resolution_; }
  float cell_center_y(std::int32_t cy) const { return origin_y_ + (static_cast<float>(cy) + 0.5f) * resolution_; }

  CellClass classify_value(std::uint8_t v) const {
    if (v == kUnknownCell || v > kOccupiedCell) return CellClass::unknown;
    if (v >= thresholds_.occupied_min) return CellClass::occupied;
    if (v <= thresholds_.free_max) return CellClass::free;
    return CellClass::unknown;
  }
  // Outside the map is unknown.
  CellClass classify(std::int32_t cx, std::int32_t cy) const {
    return contains(cx, cy) ? classify_value(at(cx, cy)) : CellClass::unknown;
  }
  bool is_occupied_value(std::uint8_t v) const { return v >= thresholds_.occupied_min && v <= kOccupiedCell; }
  bool is_occupied(std::int32_t cx, std::int32_t cy) const { return contains(cx, cy) && is_occupied_value(at(cx, cy)); }

 private:
  const std::uint8_t* cells_ = nullptr;
  std::int32_t width_ = 0;
  std::int32_t height_ = 0;
  float resolution_ = 1.0f;
  float inv_resolution_ = 1.0f;
  float origin_x_ = 0.0f;
  float origin_y_ = 0.0f;
  CellThresholds thresholds_{};
};

// A grid being filled: the runtime-capacity interface every loader and generator writes to.
class OccupancyGridBuffer {
 public:
  OccupancyGridBuffer(const OccupancyGridBuffer&) = delete;
  OccupancyGridBuffer& operator=(const OccupancyGridBuffer&) = delete;

  std::int32_t capacity_width() const { return cap_w_; }
  std::int32_t capacity_height() const { return cap_h_; }

  // Sets the size and geometry and fills every cell with `fill`; nothing changes unless the result is ok.
  MapStatus configure(std::int32_t width, std::int32_t height, float resolution, float origin_x, float origin_y,
                      std::uint8_t fill = kUnknownCell, CellThresholds thresholds = {}) {
    if (width <= 0 || height <= 0) return MapStatus::empty;
    if (width > cap_w_ || height > cap_h_) return MapStatus::too_large;
    if (!fmath::isfinite(resolution) || !(resolution > 0.0f)) return MapStatus::bad_resolution;
    if (!fmath::isfinite(origin_x) || !fmath::isfinite(origin_y)) return MapStatus::bad_origin;
    if (thresholds.occupied_min > kOccupiedCell || thresholds.free_max >= thresholds.occupied_min)
      return MapStatus::bad_thresholds;
    width_ = width;
    height_ = height;
    resolution_ = resolution;
    origin_x_ = origin_x;
    origin_y_ = origin_y;
    thresholds_ = thresholds;
    const std::int32_t n = width * height;
    for (std::int32_t i = 0; i < n; ++i) cells_[i] = fill;
    return MapStatus::ok;
  }

  std::int32_t width() const { return width_; }
  std::int32_t height() const { return height_; }
  bool contains(std::int32_t cx, std::int32_t cy) const { return cx >= 0 && cy >= 0 && cx < width_ && cy < height_; }
  // Out-of-range writes are ignored (and reported), so a generator cannot scribble past the buffer.
  bool set(std::int32_t cx, std::int32_t cy, std::uint8_t value) {
    if (!contains(cx, cy)) return false;
    cells_[cy * width_ + cx] = value;
    return true;
  }
  std::uint8_t get(std::int32_t cx, std::int32_t cy) const { return cells_[cy * width_ + cx]; }
  // Fills the axis-aligned cell rectangle [cx0, cx1] x [cy0, cy1], clipped to the map.
  void fill_rect(std::int32_t cx0, std::int32_t cy0, std::int32_t cx1, std::int32_t cy1, std::uint8_t value) {
    if (cx0 < 0) cx0 = 0;
    if (cy0 < 0) cy0 = 0;
    if (cx1 >= width_) cx1 = width_ - 1;
    if (cy1 >= height_) cy1 = height_ - 1;
    for (std::int32_t y = cy0; y <= cy1; ++y)
      for (std::int32_t x = cx0; x <= cx1; ++x) cells_[y * width_ + x] = value;
  }

  OccupancyGrid grid() const {
    if (width_ == 0) return OccupancyGrid{};
    return OccupancyGrid(cells_, width_, height_, resolution_, origin_x_, origin_y_, thresholds_);
  }

 protected:
  OccupancyGridBuffer(std::uint8_t* cells, std::int32_t cap_w, std::int32_t cap_h)
      : cells_(cells), cap_w_(cap_w), cap_h_(cap_h) {}
  ~OccupancyGridBuffer() = default;

 private:
  std::uint8_t* cells_;
  std::int32_t cap_w_;
  std::int32_t cap_h_;
  std::int32_t width_ = 0;
  std::int32_t height_ = 0;
  float resolution_ = 1.0f;
  float origin_x_ = 0.0f;
  float origin_y_ = 0.0f;
  CellThresholds thresholds_{};
};

// The owner: W_max * H_max bytes, meant to be a static object (too large for a stack on the board).
template <std::int32_t WMax, std::int32_t HMax>
class OccupancyGridStorage final : public OccupancyGridBuffer {
  static_assert(WMax > 0 && HMax > 0 && WMax <= 16384 && HMax <= 16384,
                "grid sides are limited to 16384 cells (int32 arithmetic of the distance transform)");

 public:
  static constexpr std::int32_t kMaxWidth = WMax;
  static constexpr std::int32_t kMaxHeight = HMax;
  static constexpr std::uint32_t kBytes = static_cast<std::uint32_t>(WMax) * static_cast<std::uint32_t>(HMax);

  OccupancyGridStorage() : OccupancyGridBuffer(storage_, WMax, HMax) {}

 private:
  std::uint8_t storage_[static_cast<std::uint32_t>(WMax) * static_cast<std::uint32_t>(HMax)];
};

}  // namespace est
