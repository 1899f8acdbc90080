#pragma once
// Likelihood field range finder model, Probabilistic Robotics table 6.3: for every beam that is not a max reading,
//   q *= z_hit prob(dist, sigma_hit) + z_rand / z_max,
// with dist the distance from the beam's end point to the nearest occupied cell, read from the shared Euclidean
// distance transform (cell of the end point, centre to centre, floored to 1/16 cell) and capped at max_distance.
// End points outside the map get dist = max_distance. Max readings are skipped (line 4 of the table); z_max is kept
// as a parameter only so the weights can be checked to sum to 1.
//
// The per-beam log term depends on dist only, so it is tabulated at configure() over the quantized distance
// (kLikelihoodFieldTableSize floats, 4 KiB; distances coarsened by powers of two when max_distance needs more
// entries, error then at most half a bucket). A particle-beam costs 4 multiply-adds, one distance lookup and one
// table lookup: no transcendental. Each term is >= log(z_rand / z_max) > -inf when z_rand > 0, and floored at
// kBeamLogDensityFloor otherwise.
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
  bool ready_ = false;
};

// log p(z | x, m) of table 6.3 summed over the prepared beams, max readings skipped. Returns 0 for an empty scan,
// and (beams not at max) * kBeamLogDensityFloor when the model is not ready or the pose is not finite.
inline float likelihood_field_range_finder_model(const ScanBeams& z, const Pose2& x, const Pose2& mount,
                                                 const LikelihoodField& field) {
  if (!field.ready() || !x.is_finite() || !mount.is_finite()) {
    std::int32_t n = 0;
    for (std::int32_t k = 0; k < z.count; ++k) n += z.is_max[k] ? 0 : 1;
    return static_cast<float>(n) * kBeamLogDensityFloor;
  }
  const SensorFrame f = sensor_frame(x, mount);
  float sum = 0.0f;
  for (std::int32_t k = 0; k < z.count; ++k) {
    if (z.is_max[k]) continue;
    const float r = z.range[k];
    const float ex = f.x + r * (f.c * z.ux[k] - f.s * z.uy[k]);
    const float ey = f.y + r * (f.s * z.ux[k] + f.c * z.uy[k]);
    sum += field.log_term_at(ex, ey);
  }
  return sum;
}

}  // namespace est
