#pragma once
// Feature-based map (Probabilistic Robotics ch. 6.6): landmarks with a position m_{j,x}, m_{j,y} and a signature
// m_{j,s}. The correspondence c of a measurement is the landmark's index in the map. ETL split: LandmarkMap is the
// read-only view, LandmarkMapBuffer the runtime-capacity interface, LandmarkMapStorage<N> the owner.
#include <cstdint>

#include "est/map/occupancy_grid.hpp"  // MapStatus
#include "est/math/fmath.hpp"

namespace est {

struct Landmark {
  float x = 0.0f;          // m
  float y = 0.0f;          // m
  float signature = 0.0f;  // the book's s: a numeric feature (colour, barcode id, radius ...)
};

class LandmarkMap {
 public:
  LandmarkMap() = default;
  LandmarkMap(const Landmark* landmarks, std::int32_t count) : lm_(landmarks), count_(count) {}
  std::int32_t size() const { return count_; }
  bool contains(std::int32_t j) const { return j >= 0 && j < count_; }
  const Landmark& operator[](std::int32_t j) const { return lm_[j]; }
  // Index of the first landmark whose signature equals s exactly, or -1 (a bounded linear scan).
  std::int32_t find_signature(float s) const {
    for (std::int32_t j = 0; j < count_; ++j)
      if (lm_[j].signature == s) return j;
    return -1;
  }

 private:
  const Landmark* lm_ = nullptr;
  std::int32_t count_ = 0;
};

class LandmarkMapBuffer {
 public:
  LandmarkMapBuffer(const LandmarkMapBuffer&) = delete;
  LandmarkMapBuffer& operator=(const LandmarkMapBuffer&) = delete;

  std::int32_t capacity() const { return capacity_; }
  std::int32_t size() const { return count_; }
  void clear() { count_ = 0; }
  // Appends; the new landmark's index is size() - 1. Signatures must be unique when unique_signature is set.
  MapStatus add(const Landmark& l, bool unique_signature = true) {
    if (!fmath::isfinite(l.x) || !fmath::isfinite(l.y) || !fmath::isfinite(l.signature)) return MapStatus::nonfinite;
    if (count_ >= capacity_) return MapStatus::full;
    if (unique_signature && view().find_signature(l.signature) >= 0) return MapStatus::duplicate;
    lm_[count_++] = l;
    return MapStatus::ok;
  }
  LandmarkMap view() const { return LandmarkMap(lm_, count_); }

 protected:
  LandmarkMapBuffer(Landmark* lm, std::int32_t capacity) : lm_(lm), capacity_(capacity) {}
  ~LandmarkMapBuffer() = default;

 private:
  Landmark* lm_;
  std::int32_t capacity_;
  std::int32_t count_ = 0;
};

template <std::int32_t N>
class LandmarkMapStorage final : public LandmarkMapBuffer {
  static_assert(N > 0, "capacity must be positive");

 public:
  static constexpr std::int32_t kCapacity = N;
  LandmarkMapStorage() : LandmarkMapBuffer(storage_, N) {}

 private:
  Landmark storage_[static_cast<std::uint32_t>(N)];
};

}  // namespace est
