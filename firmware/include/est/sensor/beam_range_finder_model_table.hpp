#pragma once
// Beam model of Thrun table 6.1 with z* read from a HeadingRangeTable (est/map/heading_range_table.hpp) at each
// beam's absolute heading, without an atan2 per beam: the beams' bearings in table bins are prepared once per scan
// (BeamBearings), and a particle adds its sensor heading in bins. Two overloads:
//  - (z, bearings, x, mount, table, model): the per-beam log densities summed in the order k = 0 .. K-1 exactly as
//    beam_range_finder_model() does, so the result equals beam_range_finder_model(z, x, mount, table, model) (the
//    table's atan2 path) up to the heading's rounding into bins, and differs from the exact casters' result only by
//    the table's range error. Per beam: the cast, the density (1-3 exp) and a log.
//  - (z, bearings, readings, x, mount, table, model): the fast one. The readings' terms are prepared once per scan
//    too (BeamReadings, est/sensor/beam_readings.hpp: p_short's numerator exp), each beam's density is the same
//    float as above bit for bit, and the densities are multiplied as table 6.1 writes it and taken to log space
//    once per particle (LogProduct, est/math/log_product.hpp): per beam the cast, 20-odd flops, the Gaussian's exp
//    (inline, est/math/inline_exp.hpp; only within 12 sigma of z*) and p_short's normalizer exp (only for z <= z*).
//    Within K 2^-24 + 2 ULP of the exact sum of the per-beam log densities (tested).
// Cost per particle: 2 sincos + 1 angle wrap (+ 1 log for the fast overload). Measured by bench_mcl on the Intel
// map (x86-64 host, -O3, 64 bins, N 256-16384, K 60 and 360; per-thread CPU time, medians of 3): per-beam-log
// overload 35-39 ns per particle-beam, fast overload 22-29 ns (of which the cast and the product ~6.5 ns, the
// density ~16-20 ns, and ~140 ns per particle: the sensor frame, the final log and the filter's normalization).
#include <cstdint>
#include <type_traits>

#include "est/geometry/pose2.hpp"
#include "est/map/heading_range_table.hpp"
#include "est/math/fmath.hpp"
#include "est/math/log_product.hpp"
#include "est/sensor/beam_range_finder_model.hpp"
#include "est/sensor/beam_readings.hpp"
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
    return table.valid() ? prepare(z, table.bins()) : prepare(z, 0);
  }
  // The same for any structure of `bins` headings 2 pi b / bins (e.g. ConeRayCaster); false when bins <= 0.
  bool prepare(const ScanBeams& z, std::int32_t bins) {
    count_ = 0;
    bins_ = 0;
    if (z.count > capacity_ || bins <= 0) return false;
    const float bins_per_rad = static_cast<float>(bins) / kTwoPi;
    for (std::int32_t k = 0; k < z.count; ++k) bins_of_beam_[k] = fmath::atan2(z.uy[k], z.ux[k]) * bins_per_rad;
    count_ = z.count;
    bins_ = bins;
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

namespace detail {
// Casters that walk many rays at once on this target (cast_lanes_from(): the cone casters on x86-64).
template <class C, class = void>
struct casts_lanes : std::false_type {};
template <class C>
struct casts_lanes<C, std::void_t<decltype(&C::template cast_lanes_from<1>)>> : std::true_type {};
}  // namespace detail

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
  const HeadingRangeTable::Origin o = table.origin(f.x, f.y);
  float sum = 0.0f;
  for (std::int32_t k = 0; k < z.count; ++k) {
    float dx = 0.0f, dy = 0.0f;
    f.beam(z, k, dx, dy);
    const float z_exp = table.cast_from(o, dx, dy, heading_bins + bearings.bins_of_beam[k], zm);
    sum += model.log_density(z.is_max[k] ? zm : z.range[k], z_exp);
  }
  return sum;
}

// The same, with the readings' per-scan terms prepared once (est/sensor/beam_readings.hpp) and the beams' densities
// multiplied as table 6.1 writes it (q = q * p), taken to log space once per particle (est/math/log_product.hpp):
// per beam no log and no exp for p_short's numerator. Each beam's density is bit-identical to the overload above's;
// the result differs from it only by the rounding of the product against that of the sum of logs: within
// K 2^-24 + 2 ULP of the result of the exact sum of the per-beam log densities (tested), e.g. 2.2e-5 nats for
// K = 360. Floors and refusals as above, and the readings must match the scan's beam count and the model's
// parameters (else K * kBeamLogDensityFloor).
// The loop of the overload below over any caster of heading bins (valid(), bins(), bins_per_rad(), origin(),
// cast_from(): the sensor's cell found once per particle):
// the heading table here, the exact cone caster in beam_range_finder_model_cone.hpp.
template <typename BinCaster>
inline float beam_range_finder_model_over_bins(const ScanBeams& z, const BeamBearings& bearings,
                                               const BeamReadings& readings, const Pose2& x, const Pose2& mount,
                                               const BinCaster& caster, const BeamRangeFinderModel& model) {
  const float floor_all = static_cast<float>(z.count) * kBeamLogDensityFloor;
  if (!model.ready() || !x.is_finite() || !mount.is_finite() || !caster.valid() || bearings.count != z.count ||
      bearings.bins != caster.bins() || !readings.matches(z.count, model))
    return floor_all;
  const SensorFrame f = sensor_frame(x, mount);
  const float heading_bins = fmath::normalize_angle(x.theta + mount.theta) * caster.bins_per_rad();
  const float zm = model.params().range_max;
  const typename BinCaster::Origin o = caster.origin(f.x, f.y);
  LogProduct q;
#if !defined(__arm__)
  // The host casts a chunk of beams first (a caster with cast_lanes_from(), the cone caster, walks them together in
  // AVX2 lanes where the CPU has them), then takes their densities kLanes at a time, each the float of the loop
  // below, and multiplies them in beam order: the boards' product, bit for bit (the self-test's beam_table and
  // beam_cone digests).
  constexpr std::int32_t kChunk = 64;
  float z_exp[kChunk], d[kChunk];
  for (std::int32_t k0 = 0; k0 < z.count; k0 += kChunk) {
    const std::int32_t m = z.count - k0 < kChunk ? z.count - k0 : kChunk;
    if constexpr (detail::casts_lanes<BinCaster>::value) {
      // All the chunk's rays at once, eight to a group; the last group padded with refused rays (a NaN direction:
      // no walk, its range unused).
      float dxs[kChunk], dys[kChunk], hb[kChunk];
      const std::int32_t padded = (m + 7) & ~7;
      for (std::int32_t j = 0; j < padded; ++j) {
        const std::int32_t k = k0 + (j < m ? j : 0);
        f.beam(z, k, dxs[j], dys[j]);
        if (j >= m) dxs[j] = __builtin_nanf("");
        hb[j] = heading_bins + bearings.bins_of_beam[k];
      }
      caster.template cast_lanes_from<kChunk / 8>(o, dxs, dys, hb, zm, z_exp,
                                                  static_cast<std::uint32_t>(padded / 8));
    } else {
      for (std::int32_t j = 0; j < m; ++j) {
        float dx = 0.0f, dy = 0.0f;
        f.beam(z, k0 + j, dx, dy);
        z_exp[j] = caster.cast_from(o, dx, dy, heading_bins + bearings.bins_of_beam[k0 + j], zm);
      }
    }
    model.densities(readings.reading + k0, z_exp, d, m);
    for (std::int32_t j = 0; j < m; ++j) q.mul(d[j]);
  }
#else
  for (std::int32_t k = 0; k < z.count; ++k) {
    float dx = 0.0f, dy = 0.0f;
    f.beam(z, k, dx, dy);
    const float z_exp = caster.cast_from(o, dx, dy, heading_bins + bearings.bins_of_beam[k], zm);
    q.mul(model.density(readings.reading[k], z_exp));
  }
#endif
  return q.log();
}

inline float beam_range_finder_model(const ScanBeams& z, const BeamBearings& bearings, const BeamReadings& readings,
                                     const Pose2& x, const Pose2& mount, const HeadingRangeTable& table,
                                     const BeamRangeFinderModel& model) {
  return beam_range_finder_model_over_bins(z, bearings, readings, x, mount, table, model);
}

}  // namespace est
