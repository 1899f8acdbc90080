#pragma once
// Beam model of Thrun table 6.1 with z* cast exactly by the lane caster (est/map/lane_ray_caster.hpp) at each
// beam's absolute heading, without an atan2 per beam: the beams' bearings in the caster's heading bins are prepared
// once per scan (BeamBearings of beam_range_finder_model_table.hpp, prepare(z, caster.bins())), and a particle adds
// its sensor heading in bins to pick each beam's nearest lane heading. The lane caster returns GridRayCaster's
// float on every ray, so each beam's density is the exact caster's bit for bit; the readings' terms are prepared
// once per scan (BeamReadings) and the densities multiplied and taken to log space once per particle (LogProduct),
// as the heading-table overload does: within K 2^-24 + 2 ULP of the exact sum of per-beam log densities (tested).
// Cost per particle: 2 sincos + 1 angle wrap + 1 log; per beam the cast (a binary search per lane crossed, ~2
// lanes and ~2 exact slab tests on the Intel map) and the density. bench_sensor_models and bench_mcl.<board> give
// the figures (README, "Benchmarks" and "Budgets on the board").
#include <cstdint>

#include "est/geometry/pose2.hpp"
#include "est/map/lane_ray_caster.hpp"
#include "est/math/fmath.hpp"
#include "est/math/log_product.hpp"
#include "est/sensor/beam_range_finder_model.hpp"
#include "est/sensor/beam_range_finder_model_table.hpp"
#include "est/sensor/beam_readings.hpp"
#include "est/sensor/range_scan.hpp"

namespace est {

// log p(z | x, m) of table 6.1 with z* from the lane caster. Returns K * kBeamLogDensityFloor when the model is not
// configured, the pose is not finite, the caster is not built, or the bearings or readings were not prepared for
// this scan, caster and model; 0 for an empty scan.
inline float beam_range_finder_model(const ScanBeams& z, const BeamBearings& bearings, const BeamReadings& readings,
                                     const Pose2& x, const Pose2& mount, const LaneRayCaster& lanes,
                                     const BeamRangeFinderModel& model) {
  return beam_range_finder_model_over_bins(z, bearings, readings, x, mount, lanes, model);
}

}  // namespace est
