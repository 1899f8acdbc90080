#pragma once
// Beam model of Thrun table 6.1 with z* read from a HeadingRangeTable (est/map/heading_range_table.hpp) at each
// beam's absolute heading, without an atan2 per beam: the beams' bearings in table bins are prepared once per scan
// (BeamBearings), and a particle adds its sensor heading in bins. The density is BeamRangeFinderModel's own, and a
// particle's beams are summed in the order k = 0 .. K-1 exactly as beam_range_finder_model() does, so the result
// equals beam_range_finder_model(z, x, mount, table, model) (the table's atan2 path) up to the heading's rounding
// into bins, and differs from the exact casters' result only by the table's range error.
// Cost per particle: 2 sincos + 1 angle wrap; per beam 2 table loads, ~15 flops and the density (~11 ns on the host).
#include <cstdint>

#include "est/geometry/pose2.hpp"
#include "est/map/heading_range_table.hpp"
#include "est/math/fmath.hpp"
#include "est/sensor/beam_range_finder_model.hpp"
#include "est/sensor/range_scan.hpp"

namespace est {

// Read-only view: bearing of kept beam k in the sensor frame, in bins of a table with `bins` headings.
struct BeamBearings {
  const float* bins_of_beam = nullptr;
  std::int32_t count = 0;
  std::int32_t bins = 0;
};

class BeamBearingsBuffer {
 public:
  BeamBearingsBuffer(const BeamBearingsBuffer&) = delete;
  BeamBearingsBuffer& operator=(const BeamBearingsBuffer&) = delete;

  // K atan2, once per scan. False (and an empty view) when the scan has more beams than the capacity or the table
  // is invalid.
  bool prepare(const ScanBeams& z, const HeadingRangeTable& table) {
    count_ = 0;
    bins_ = 0;
    if (z.count > capacity_ || !table.valid()) return false;
    for (std::int32_t k = 0; k < z.count; ++k) bins_of_beam_[k] = fmath::atan2(z.uy[k], z.ux[k]) * table.bins_per_rad();
    count_ = z.count;
    bins_ = table.bins();
    return true;
  }
  BeamBearings view() const { return {bins_of_beam_, count_, bins_}; }

 protected:
  BeamBearingsBuffer(float* bins_of_beam, std::int32_t capacity) : bins_of_beam_(bins_of_beam), capacity_(capacity) {}
  ~BeamBearingsBuffer() = default;

 private:
  float* bins_of_beam_;
  std::int32_t capacity_;
  std::int32_t count_ = 0;
  std::int32_t bins_ = 0;
};

template <std::int32_t KMax>
class BeamBearingsStorage final : public BeamBearingsBuffer {
  static_assert(KMax > 0, "capacity must be positive");

 public:
  BeamBearingsStorage() : BeamBearingsBuffer(bins_, KMax) {}

 private:
  float bins_[static_cast<std::uint32_t>(KMax)];
};

// log p(z | x, m) of table 6.1 with z* from the heading table. Returns K * kBeamLogDensityFloor when the model is not
// configured, the pose is not finite, or the bearings were not prepared for this scan and table (count or bins
// differ); 0 for an empty scan.
inline float beam_range_finder_model(const ScanBeams& z, const BeamBearings& bearings, const Pose2& x,
                                     const Pose2& mount, const HeadingRangeTable& table,
                                     const BeamRangeFinderModel& model) {
  const float floor_all = static_cast<float>(z.count) * kBeamLogDensityFloor;
  if (!model.ready() || !x.is_finite() || !mount.is_finite() || !table.valid() || bearings.count != z.count ||
      bearings.bins != table.bins())
    return floor_all;
  const SensorFrame f = sensor_frame(x, mount);
  // The sensor heading in bins, within [-T/2, T/2]; each beam's bearing adds at most T/2 more.
  const float heading_bins = fmath::normalize_angle(x.theta + mount.theta) * table.bins_per_rad();
  const float zm = model.params().range_max;
  float sum = 0.0f;
  for (std::int32_t k = 0; k < z.count; ++k) {
    const float dx = f.c * z.ux[k] - f.s * z.uy[k];
    const float dy = f.s * z.ux[k] + f.c * z.uy[k];
    const float z_exp = table.cast_bins(f.x, f.y, dx, dy, heading_bins + bearings.bins_of_beam[k], zm);
    sum += model.log_density(z.is_max[k] ? zm : z.range[k], z_exp);
  }
  return sum;
}

}  // namespace est
