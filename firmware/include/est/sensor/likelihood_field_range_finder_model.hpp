#pragma once
// Likelihood field range finder model, Probabilistic Robotics table 6.3: for every beam that is not a max reading,
//   q *= z_hit prob(dist, sigma_hit) + z_rand / z_max,
// with dist the distance from the beam's end point to the nearest occupied cell, read from the shared Euclidean
// distance transform (cell of the end point, centre to centre, floored to 1/16 cell) and capped at max_distance.
// End points outside the map get dist = max_distance. Max readings are skipped (line 4 of the table); z_max is kept
// as a parameter only so the weights can be checked to sum to 1.
//
// The per-beam log term depends on dist only, so it is tabulated at configure() over the quantized distance
// (kLikelihoodFieldTableSize floats, 4 KiB, and as many quantized uint16, 2 KiB; distances coarsened by powers of
// two when max_distance needs more entries, error then at most half a bucket). A particle-beam costs 4 multiplies
// and 4 adds, one distance lookup and one table lookup: no transcendental. Each term is >= log(z_rand / z_max) > -inf
// when z_rand > 0, and floored at kBeamLogDensityFloor otherwise.
//
// QUANTIZED SUM. The model sums the terms as integers: each term is stored as q = round((T0 - term) 256), its
// distance below the largest term T0 = log_term_max() in steps of 1/256 nat (uint16), and a scan's log-likelihood is
// hits T0 - (sum of q) / 256 (lf_log_likelihood). Integer sums are exact in any order, so the batched form (any
// blocking, any vector width) gives the scalar model's bits; the quantization moves a term by at most 1/512 nat.
// End points are computed in cell units of the map padded by one cell on every side (lf_cell_coordinate,
// lf_beam_offset: the same float expressions in both forms), their cell by truncation; any cell of the pad, and any
// end point off the map, has the term of the capped distance.
//
// Not a normalized density over z in general (the book, ch. 6.4): along one beam facing a wall across an open map,
// the continuous part integrates to z_hit + z_rand and the skipped max reading carries z_max (tested).
#include <cstdint>

#include "est/geometry/pose2.hpp"
#include "est/map/distance_transform.hpp"
#include "est/map/occupancy_grid.hpp"
#include "est/math/fmath.hpp"
#include "est/math/normal.hpp"
#include "est/sensor/beam_range_finder_model.hpp"  // SensorModelStatus, kBeamLogDensityFloor
#include "est/sensor/range_scan.hpp"

namespace est {

inline constexpr std::int32_t kLikelihoodFieldTableSize = 1024;
// Quantization of the per-beam terms (see the header): 256 steps per nat, stored as uint16.
inline constexpr float kLikelihoodFieldStepsPerNat = 256.0f;
inline constexpr float kLikelihoodFieldNatsPerStep = 1.0f / 256.0f;

// A world coordinate in cell units of the padded grid: (v - origin) / resolution + 1, clamped to +-2^24 (NaN to the
// low end) so that an end point's conversion to an integer is defined for any particle.
inline float lf_cell_coordinate(float v, float origin, float inv_resolution) {
  constexpr float kLimit = 0x1p24f;
  const float g = (v - origin) * inv_resolution + 1.0f;
  const float lo = g > -kLimit ? g : -kLimit;
  return lo < kLimit ? lo : kLimit;
}
// A beam's end point in the sensor frame in cell units, r u / resolution, clamped like the coordinates.
inline float lf_beam_offset(float r, float u, float inv_resolution) {
  constexpr float kLimit = 0x1p24f;
  const float g = (r * u) * inv_resolution;
  const float lo = g > -kLimit ? g : -kLimit;
  return lo < kLimit ? lo : kLimit;
}
// log p(z | x, m) from the integer sum of the quantized terms of `hits` beams (see the header).
inline float lf_log_likelihood(std::int32_t hits, float log_peak, std::uint32_t steps) {
  return static_cast<float>(hits) * log_peak - static_cast<float>(steps) * kLikelihoodFieldNatsPerStep;
}

struct LikelihoodFieldParams {
  float z_hit = 0.90f;
  float z_max = 0.05f;
  float z_rand = 0.05f;
  float sigma_hit = 0.2f;     // m
  float range_max = 30.0f;    // m: the book's z_max as a range
  float max_distance = 2.0f;  // m: distances are capped here (and used for end points off the map)
};

class LikelihoodField {
 public:
  // The grid gives the geometry (origin, resolution); the transform must have been built from it.
  SensorModelStatus configure(const LikelihoodFieldParams& p, const OccupancyGrid& grid, const DistanceTransform& edt) {
    ready_ = false;
    const float all[6] = {p.z_hit, p.z_max, p.z_rand, p.sigma_hit, p.range_max, p.max_distance};
    for (float v : all)
      if (!fmath::isfinite(v)) return SensorModelStatus::nonfinite;
    if (p.z_hit < 0.0f || p.z_max < 0.0f || p.z_rand < 0.0f ||
        fmath::abs(p.z_hit + p.z_max + p.z_rand - 1.0f) > 1e-3f)
      return SensorModelStatus::bad_weights;
    if (!(p.sigma_hit > 0.0f)) return SensorModelStatus::bad_sigma;
    if (!(p.range_max > 0.0f)) return SensorModelStatus::bad_range;
    if (!(p.max_distance > 0.0f)) return SensorModelStatus::bad_distance;
    if (!grid.valid() || !edt.valid() || edt.width() != grid.width() || edt.height() != grid.height())
      return SensorModelStatus::not_ready;
    p_ = p;
    grid_ = grid;
    edt_ = edt;

    // Largest quantized distance that is still below the cap, then the bucket shift that fits it in the table.
    const float units_per_metre = 16.0f * grid.inv_resolution();
    float cap_units_f = p.max_distance * units_per_metre;
    if (cap_units_f > 65534.0f) cap_units_f = 65534.0f;
    cap_units_ = static_cast<std::int32_t>(cap_units_f);
    shift_ = 0;
    while ((cap_units_ >> shift_) >= kLikelihoodFieldTableSize - 1 && shift_ < 16) ++shift_;
    const std::int32_t last = cap_units_ >> shift_;
    const float log_sigma = fmath::log(p.sigma_hit);
    const float rand_density = p.z_rand / p.range_max;
    for (std::int32_t j = 0; j <= last; ++j) {
      float units = static_cast<float>(j << shift_);
      if (shift_ > 0) units += 0.5f * static_cast<float>(1 << shift_);
      float d = units * edt.metres_per_unit();
      if (d > p.max_distance || j == last) d = p.max_distance;
      const float dens = p.z_hit * fmath::exp(log_normal_density(d, p.sigma_hit, log_sigma)) + rand_density;
      table_[j] = dens > 1e-30f ? fmath::log(dens) : kBeamLogDensityFloor;
    }
    for (std::int32_t j = 0; j <= last; ++j) {
      float q = (table_[0] - table_[j]) * kLikelihoodFieldStepsPerNat + 0.5f;  // >= 0.5: the table falls with j
      if (q > 65535.0f) q = 65535.0f;
      steps_[j] = static_cast<std::uint16_t>(q);
    }
    last_ = last;
    ready_ = true;
    return SensorModelStatus::ok;
  }
  bool ready() const { return ready_; }
  const LikelihoodFieldParams& params() const { return p_; }

  // log(z_hit prob(dist, sigma) + z_rand / z_max) for an end point in world coordinates.
  float log_term_at(float ex, float ey) const {
    const float gx = (ex - grid_.origin_x()) * grid_.inv_resolution();
    const float gy = (ey - grid_.origin_y()) * grid_.inv_resolution();
    if (!(gx >= 0.0f && gy >= 0.0f && gx < static_cast<float>(grid_.width()) &&
          gy < static_cast<float>(grid_.height())))
      return table_[last_];
    std::int32_t cx = static_cast<std::int32_t>(gx);
    std::int32_t cy = static_cast<std::int32_t>(gy);
    if (cx >= grid_.width()) cx = grid_.width() - 1;
    if (cy >= grid_.height()) cy = grid_.height() - 1;
    std::int32_t u = edt_.data()[cy * grid_.width() + cx];
    if (u > cap_units_) u = cap_units_;
    return table_[u >> shift_];
  }
  // The quantized term (steps below log_term_max()) of cell (ix, iy) of the map padded by one cell: map cell
  // (ix - 1, iy - 1), or the capped distance's for the pad and beyond.
  std::uint16_t steps_at_cell(std::int32_t ix, std::int32_t iy) const {
    const std::uint32_t cx = static_cast<std::uint32_t>(ix) - 1u, cy = static_cast<std::uint32_t>(iy) - 1u;
    if (cx >= static_cast<std::uint32_t>(grid_.width()) || cy >= static_cast<std::uint32_t>(grid_.height()))
      return steps_[last_];
    std::int32_t u = edt_.data()[cy * static_cast<std::uint32_t>(grid_.width()) + cx];
    if (u > cap_units_) u = cap_units_;
    return steps_[u >> shift_];
  }
  const OccupancyGrid& grid() const { return grid_; }
  // Distance (m) the term at an end point was computed for: the capped, quantized distance-transform value.
  float distance_at(float ex, float ey) const {
    std::int32_t cx = 0, cy = 0;
    if (!grid_.world_to_cell(ex, ey, cx, cy)) return p_.max_distance;
    const float d = edt_.metres(cx, cy);
    return d < p_.max_distance ? d : p_.max_distance;
  }
  // The largest per-beam term (an end point on an obstacle; the table falls with the distance): the upper bound of
  // one factor that augmented MCL's recovery statistic asks for (MeasurementScale::log_peak).
  float log_term_max() const { return table_[0]; }
  std::int32_t table_entries() const { return last_ + 1; }
  std::int32_t bucket_shift() const { return shift_; }

 private:
  LikelihoodFieldParams p_{};
  OccupancyGrid grid_{};
  DistanceTransform edt_{};
  std::int32_t cap_units_ = 0;
  std::int32_t shift_ = 0;
  std::int32_t last_ = 0;
  float table_[kLikelihoodFieldTableSize] = {};
  std::uint16_t steps_[kLikelihoodFieldTableSize] = {};
  bool ready_ = false;
};

// log p(z | x, m) of table 6.3 summed over the prepared beams, max readings skipped, with the quantized terms (see
// the header). Returns 0 for an empty scan, and (beams not at max) * kBeamLogDensityFloor when the model is not
// ready or the pose is not finite.
inline float likelihood_field_range_finder_model(const ScanBeams& z, const Pose2& x, const Pose2& mount,
                                                 const LikelihoodField& field) {
  if (!field.ready() || !x.is_finite() || !mount.is_finite()) {
    std::int32_t n = 0;
    for (std::int32_t k = 0; k < z.count; ++k) n += z.is_max[k] ? 0 : 1;
    return static_cast<float>(n) * kBeamLogDensityFloor;
  }
  const SensorFrame f = sensor_frame(x, mount);
  const OccupancyGrid& g = field.grid();
  const float inv = g.inv_resolution();
  const float px = lf_cell_coordinate(f.x, g.origin_x(), inv), py = lf_cell_coordinate(f.y, g.origin_y(), inv);
  std::uint32_t steps = 0;
  std::int32_t hits = 0;
  for (std::int32_t k = 0; k < z.count; ++k) {
    if (z.is_max[k]) continue;
    const float bx = lf_beam_offset(z.range[k], z.ux[k], inv), by = lf_beam_offset(z.range[k], z.uy[k], inv);
    const float gx = px + (f.c * bx - f.s * by);
    const float gy = py + (f.s * bx + f.c * by);
    steps += field.steps_at_cell(static_cast<std::int32_t>(gx), static_cast<std::int32_t>(gy));
    ++hits;
  }
  return lf_log_likelihood(hits, field.log_term_max(), steps);
}

}  // namespace est
