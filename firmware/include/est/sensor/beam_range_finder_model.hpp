#pragma once
// Beam model of range finders, Probabilistic Robotics table 6.1 (eq. 6.4-6.12): per beam the mixture
//   p(z | z*) = z_hit p_hit + z_short p_short + z_max p_max + z_rand p_rand,
//   p_hit   = N(z; z*, sigma_hit^2) truncated to [0, z_max] and divided by its mass there (eq. 6.5-6.6),
//   p_short = lambda e^{-lambda z} on [0, z*], divided by 1 - e^{-lambda z*} (eq. 6.7-6.8),
//   p_max   = a discrete atom at z_max of mass z_max (the weight). For density comparisons the atom is spread as a
//             uniform density 1 / max_bin_width over a bin of that width: a max reading's density is
//             z_hit p_hit(z_max) + z_short p_short(z_max) + z_max / max_bin_width (the continuous parts carry no
//             mass at a point, so the total mass stays 1),
//   p_rand  = 1 / z_max on [0, z_max) (eq. 6.11).
// So the continuous parts integrate to z_hit + z_short + z_rand over [0, z_max) and the atom adds z_max: 1 in all
// (tested). One exception, stated: when z* < 1e-6 / lambda (the sensor is inside an obstacle) p_short has no room
// and is 0, and the mixture then integrates to 1 - z_short.
//
// Log-likelihoods are sums of per-beam log densities (per metre), each floored at kBeamLogDensityFloor
// (log 1e-30), so a scan's log-likelihood is never -inf or NaN; a non-finite pose gets the floor on every beam.
//
// Speed without changing a bit: the Gaussian's and p_short's exp are fmath::exp inlined (est/math/inline_exp.hpp,
// the same bits), p_hit's truncation mass for a ray with no hit (z* = z_max) is computed once in configure(), what
// depends on the reading alone can be prepared once per scan (reading(), est/sensor/beam_readings.hpp), and on the
// host densities() takes four beams at a time in SSE2 lanes (the same bits).
#include <cstdint>

#include "est/geometry/pose2.hpp"
#include "est/math/fmath.hpp"
#include "est/math/inline_exp.hpp"
#include "est/math/normal.hpp"
#include "est/sensor/range_scan.hpp"
#if !defined(__arm__)
#include "est/math/lanes.hpp"
#endif

namespace est {

inline constexpr float kBeamLogDensityFloor = -69.0775527898f;  // log(1e-30)

enum class SensorModelStatus : std::uint8_t {
  ok = 0,
  nonfinite,      // a parameter is NaN or infinite
  bad_weights,    // a weight is negative, or the weights do not sum to 1 within 1e-3
  bad_sigma,      // a standard deviation <= 0
  bad_lambda,     // lambda_short <= 0
  bad_range,      // range_max <= 0
  bad_bin,        // max_bin_width <= 0
  bad_distance,   // likelihood field max_distance <= 0
  not_ready,      // configure() was not called or failed, or the map is missing
};

struct BeamModelParams {
  float z_hit = 0.80f;
  float z_short = 0.10f;
  float z_max = 0.05f;
  float z_rand = 0.05f;
  float sigma_hit = 0.2f;      // m
  float lambda_short = 0.5f;   // 1/m
  float range_max = 30.0f;     // m: the book's z_max as a range
  float max_bin_width = 0.05f; // m: width of the bin a max reading's atom is spread over
};

class BeamRangeFinderModel {
 public:
  SensorModelStatus configure(const BeamModelParams& p) {
    ready_ = false;
    const float all[8] = {p.z_hit, p.z_short, p.z_max, p.z_rand, p.sigma_hit, p.lambda_short, p.range_max,
                          p.max_bin_width};
    for (float v : all)
      if (!fmath::isfinite(v)) return SensorModelStatus::nonfinite;
    if (p.z_hit < 0.0f || p.z_short < 0.0f || p.z_max < 0.0f || p.z_rand < 0.0f) return SensorModelStatus::bad_weights;
    const float sum = p.z_hit + p.z_short + p.z_max + p.z_rand;
    if (fmath::abs(sum - 1.0f) > 1e-3f) return SensorModelStatus::bad_weights;
    if (!(p.sigma_hit > 0.0f)) return SensorModelStatus::bad_sigma;
    if (!(p.lambda_short > 0.0f)) return SensorModelStatus::bad_lambda;
    if (!(p.range_max > 0.0f)) return SensorModelStatus::bad_range;
    if (!(p.max_bin_width > 0.0f)) return SensorModelStatus::bad_bin;
    p_ = p;
    inv_sigma_ = 1.0f / p.sigma_hit;
    hit_coeff_ = p.z_hit * 0.39894228040143267794f * inv_sigma_;
    rand_density_ = p.z_rand / p.range_max;
    max_density_ = p.z_max / p.max_bin_width;
    mass_at_max_ = hit_mass((0.0f - p.range_max) * inv_sigma_, (p.range_max - p.range_max) * inv_sigma_);
    ready_ = true;
    log_typical_hit_ = typical_log_density_of_hits();
    return SensorModelStatus::ok;
  }
  bool ready() const { return ready_; }
  const BeamModelParams& params() const { return p_; }

  // The log density of a reading exactly where a correct pose puts it: a max reading with no obstacle on the ray
  // (z* = z_max), or a reading at its expected range away from the ends of [0, z_max] (p_hit's mode and p_rand;
  // p_short left out: it exceeds a fraction of p_hit only within ~1/lambda of the sensor).
  float log_peak(bool max_reading) const {
    return fmath::log(max_reading ? max_density_ + hit_coeff_ / mass_at_max_ : hit_coeff_ + rand_density_);
  }

  // The log density a correct pose's reading scores on average when it is a hit, E[log p(z | z*)] over
  // z ~ N(z*, sigma_hit^2) (the mixture's density, at z* = range_max / 2), for a reading that is not a max reading;
  // a max reading with no obstacle on the ray is exact (log_peak(true)). The origin of augmented MCL's recovery
  // statistic (est/loop/beam_scan.hpp beam_scale): a scan of a correct pose scores about this per beam, outliers
  // aside, where log_peak(false) sits 0.5 nats higher (a Gaussian's mean log density is its peak's minus 1/2), which
  // no pose reaches: measured from the peak, a filter tracking exactly in the office scored -0.4 to -0.6 nats a beam
  // and injected 14-18 % random particles while localized, its w_slow starting at the peak (issue 37).
  float log_typical(bool max_reading) const { return max_reading ? log_peak(true) : log_typical_hit_; }

  // Mixture density (per metre) of reading z given the expected range z_exp, both clamped to [0, range_max];
  // z >= range_max is a max reading. Non-finite z or z_exp give 0 (the caller floors the log).
  float density(float z, float z_exp) const {
    if (!fmath::isfinite(z) || !fmath::isfinite(z_exp)) return 0.0f;
    const Reading r = clamped(z);  // p_short's numerator only where it counts (z <= z*)
    z_exp = clamp_range(z_exp);
    const float p = add_hit(r.base, r.z, z_exp);
    return p_.z_short > 0.0f && r.z <= z_exp ? add_short(p, short_numerator(r.z), r.z, z_exp) : p;
  }

  float log_density(float z, float z_exp) const {
    const float p = density(z, z_exp);
    return p > 1e-30f ? fmath::log(p) : kBeamLogDensityFloor;
  }

  // The terms of a reading that do not depend on z*, prepared once per scan (est/sensor/beam_readings.hpp), so a
  // particle-beam pays no exp for p_short's numerator. density(reading(z), z_exp) == density(z, z_exp) bit for
  // bit for every z and finite z_exp (the same operations in the same order; tested).
  struct Reading {
    float z = 0.0f;          // clamped to [0, range_max]
    float base = 0.0f;       // z_max / max_bin_width for a max reading, else z_rand / range_max
    float short_num = 0.0f;  // z_short lambda e^{-lambda z}; 0 when z_short = 0
  };
  Reading reading(float z) const {
    if (!fmath::isfinite(z)) {
      Reading r;
      r.z = __builtin_nanf("");  // no hit, no short, base 0: density 0, as density(z, z_exp) gives
      return r;
    }
    Reading r = clamped(z);
    if (p_.z_short > 0.0f) r.short_num = short_numerator(r.z);
    return r;
  }
  // z_exp must be finite (a ray caster's range); it is clamped to [0, range_max].
  float density(const Reading& r, float z_exp) const {
    z_exp = clamp_range(z_exp);
    float p = add_hit(r.base, r.z, z_exp);
    if (p_.z_short > 0.0f) p = add_short(p, r.short_num, r.z, z_exp);
    return p;
  }

  // out[k] = density(r[k], z_exp[k]) for k < n, bit for bit. On the host kLanes beams at a time (est/math/lanes.hpp:
  // the same operations in the same order, selects instead of the branches, the truncation mass by lanes::normal_cdf
  // only when a lane needs it; a group where lambda z* >= 85, outside the lanes' exp, is taken one beam at a time).
  // The boards, whose FPU gains nothing from lanes, take the scalar density.
  void densities(const Reading* r, const float* z_exp, float* out, std::int32_t n) const {
    std::int32_t k = 0;
#if !defined(__arm__)
    constexpr std::int32_t kL = static_cast<std::int32_t>(lanes::kLanes);
    for (; k + kL <= n; k += kL)
      if (!densities_lanes(r + k, z_exp + k, out + k))
        for (std::int32_t j = k; j < k + kL; ++j) out[j] = density(r[j], z_exp[j]);
#endif
    for (; k < n; ++k) out[k] = density(r[k], z_exp[k]);
  }

 private:
  // A finite reading clamped to [0, range_max] with its max-or-rand constant; short_num left 0.
  Reading clamped(float z) const {
    const bool is_max = z >= p_.range_max;
    Reading r;
    r.z = is_max ? p_.range_max : (z < 0.0f ? 0.0f : z);
    r.base = is_max ? max_density_ : rand_density_;
    return r;
  }
  float clamp_range(float z) const { return z < 0.0f ? 0.0f : (z > p_.range_max ? p_.range_max : z); }
  float short_numerator(float z) const { return p_.z_short * p_.lambda_short * fmath::exp(-p_.lambda_short * z); }

  // p_hit: beyond 12 sigma the Gaussian is below 1e-31 relative, under the floor. (Computing it unconditionally and
  // selecting measured slower on the host than the branch, bench_mcl.)
  float add_hit(float p, float z, float z_exp) const {
    const float u = (z - z_exp) * inv_sigma_;
    if (!(u > -12.0f && u < 12.0f)) return p;
    // Mass of N(z*, sigma^2) in [0, z_max]; exactly 1 to float precision more than 5.5 sigma from both ends. A ray
    // with no hit has z* = range_max exactly: its mass is computed once, in configure().
    float mass = 1.0f;
    const float a = (0.0f - z_exp) * inv_sigma_;
    const float b = (p_.range_max - z_exp) * inv_sigma_;
    if (a > -5.5f || b < 5.5f) mass = z_exp == p_.range_max ? mass_at_max_ : hit_mass(a, b);
    const float hit = hit_coeff_ * imath::exp(-0.5f * u * u);
    return p + (mass == 1.0f ? hit : hit / mass);  // x / 1 is x: no division away from the ends, the same float
  }
  // log_typical(false): the midpoint rule over u = (z - z*) / sigma in [-6, 6], 97 points, its weights the normal
  // density normalized to sum 1 (configure()'s only loop: bounded).
  float typical_log_density_of_hits() const {
    constexpr std::int32_t kPoints = 97;
    constexpr float kDu = 12.0f / static_cast<float>(kPoints);
    const float z_exp = 0.5f * p_.range_max;
    float sum_w = 0.0f, sum = 0.0f;
    for (std::int32_t i = 0; i < kPoints; ++i) {
      const float u = -6.0f + (static_cast<float>(i) + 0.5f) * kDu;
      const float w = fmath::exp(-0.5f * u * u);
      float z = z_exp + u * p_.sigma_hit;
      if (z >= p_.range_max) z = p_.range_max - 1e-6f * p_.range_max;  // a continuous reading, not a max one
      sum_w += w;
      sum += w * log_density(z, z_exp);
    }
    return sum / sum_w;
  }
  static float hit_mass(float a, float b) {
    const float mass = normal_cdf(b) - normal_cdf(a);
    return mass < 1e-30f ? 1e-30f : mass;
  }
  // p_short on [0, z*], from its numerator z_short lambda e^{-lambda z}.
  float add_short(float p, float short_num, float z, float z_exp) const {
    const float x = p_.lambda_short * z_exp;
    if (!(z <= z_exp && x >= 1e-6f)) return p;
    // 1 - e^{-x} without cancellation for small x
    const float norm = x < 1e-3f ? x * (1.0f - 0.5f * x * (1.0f - x * (1.0f / 3.0f))) : 1.0f - imath::exp(-x);
    return p + short_num / norm;
  }

#if !defined(__arm__)
  // density() of kLanes beams; false (out untouched) when a lane's p_short normalizer needs exp below -85.
  bool densities_lanes(const Reading* r, const float* z_exp, float* out) const {
    using lanes::F;
    using lanes::I;
    const F rm = lanes::splat(p_.range_max);
    F ze = lanes::load(z_exp);
    ze = ze < 0.0f ? lanes::splat(0.0f) : (ze > rm ? rm : ze);  // clamp_range
    const F z = {r[0].z, r[1].z, r[2].z, r[3].z};
    const F u = (z - ze) * inv_sigma_;
    const I hit_in = (u > -12.0f) & (u < 12.0f);
    const F a = (0.0f - ze) * inv_sigma_;
    const F b = (rm - ze) * inv_sigma_;
    const I near_end = hit_in & ((a > -5.5f) | (b < 5.5f));
    F g;
    lanes::exp(hit_in ? (-0.5f * u) * u : lanes::splat(0.0f), g);
    F hit = hit_coeff_ * g;
    if (lanes::any(near_end)) {
      // hit_mass(): Phi(b) - Phi(a), where b >= 0 >= a. Each Phi only where a lane needs it: beyond its tails' cut
      // Phi(b) is 1 and Phi(a) 0, as normal_cdf() returns there.
      const I need = near_end & (ze != rm);
      const F cb = lanes::any(need & lanes::normal_cdf_computes(b)) ? lanes::normal_cdf(b) : lanes::splat(1.0f);
      const F ca = lanes::any(need & lanes::normal_cdf_computes(a)) ? lanes::normal_cdf(a) : lanes::splat(0.0f);
      F m = cb - ca;
      m = m < 1e-30f ? lanes::splat(1e-30f) : m;
      const F mass = near_end ? (need ? m : lanes::splat(mass_at_max_)) : lanes::splat(1.0f);
      hit = (mass == 1.0f) ? hit : hit / mass;  // x / 1 is x: no division away from the ends, the same float
    }
    F p = F{r[0].base, r[1].base, r[2].base, r[3].base};
    p = hit_in ? p + hit : p;
    if (p_.z_short > 0.0f) {
      const F x = p_.lambda_short * ze;
      const I short_in = (z <= ze) & (x >= 1e-6f);
      F e;
      const I exp_in = lanes::exp(short_in ? -x : lanes::splat(0.0f), e);
      if (lanes::any(short_in & ~exp_in)) return false;  // lambda z* >= 85: fmath::exp's underflow path
      const F small = x * (1.0f - 0.5f * x * (1.0f - x * (1.0f / 3.0f)));
      const F norm = short_in ? ((x < 1e-3f) ? small : 1.0f - e) : lanes::splat(1.0f);
      if (lanes::any(short_in)) {
        const F sn = {r[0].short_num, r[1].short_num, r[2].short_num, r[3].short_num};
        p = short_in ? p + sn / norm : p;
      }
    }
    lanes::store(out, p);
    return true;
  }
#endif

  BeamModelParams p_{};
  float inv_sigma_ = 1.0f;
  float hit_coeff_ = 0.0f;
  float rand_density_ = 0.0f;
  float max_density_ = 0.0f;
  float mass_at_max_ = 1.0f;  // p_hit's mass at z* = range_max (a ray with no hit), the same float hit_mass() gives
  float log_typical_hit_ = 0.0f;  // log_typical(false)
  bool ready_ = false;
};

// log p(z | x, m) of table 6.1: the sum over the prepared beams of the per-beam log density, with z* ray cast by
// `caster` (GridRayCaster or DistanceTransformRayCaster, or anything with the same cast()) from the sensor pose
// x (+) mount. Cost per particle: 2 sincos + K ray casts + K densities. Returns 0 for an empty scan and
// K * kBeamLogDensityFloor when the model is not configured or the pose is not finite.
template <class Caster>
float beam_range_finder_model(const ScanBeams& z, const Pose2& x, const Pose2& mount, const Caster& caster,
                              const BeamRangeFinderModel& model) {
  const float floor_all = static_cast<float>(z.count) * kBeamLogDensityFloor;
  if (!model.ready() || !x.is_finite() || !mount.is_finite()) return floor_all;
  const SensorFrame f = sensor_frame(x, mount);
  const float zm = model.params().range_max;
  float sum = 0.0f;
  for (std::int32_t k = 0; k < z.count; ++k) {
    float dx = 0.0f, dy = 0.0f;
    f.beam(z, k, dx, dy);
    const float z_exp = caster.cast(f.x, f.y, dx, dy, zm);
    sum += model.log_density(z.is_max[k] ? zm : z.range[k], z_exp);
  }
  return sum;
}

}  // namespace est
