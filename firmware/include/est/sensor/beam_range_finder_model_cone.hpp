#pragma once
// Beam model of Thrun table 6.1 with z* cast exactly by the cone caster (est/map/cone_ray_caster.hpp) at each
// beam's absolute heading, without an atan2 per beam: the beams' bearings in the caster's heading bins are prepared
// once per scan (BeamBearings, prepare(z, caster.bins())), and a particle adds its sensor heading in bins to pick
// each beam's table. The cone caster returns GridRayCaster's float (but where a jump lands within rounding of a cell
// corner), so each beam's density is the exact caster's; the readings' terms are prepared once per scan
// (BeamReadings) and the densities multiplied and taken to log space once per particle (LogProduct), as the lane
// and heading-table overloads do. Cost per particle: 2 sincos + 1 angle wrap + 1 log; per beam the cast (~2.3 jumps
// and ~1.4 exact steps on the Intel map) and the density. bench_sensor_models and bench_mcl.<board> give the
// figures (README, "Benchmarks" and "Budgets on the board").
#include "est/geometry/pose2.hpp"
#include "est/map/cone_ray_caster.hpp"
#include "est/sensor/beam_range_finder_model.hpp"
#include "est/sensor/beam_range_finder_model_table.hpp"
#include "est/sensor/beam_readings.hpp"
#include "est/sensor/range_scan.hpp"

namespace est {

// log p(z | x, m) of table 6.1 with z* from the cone caster. Returns K * kBeamLogDensityFloor when the model is not
// configured, the pose is not finite, the caster is not built, or the bearings or readings were not prepared for
// this scan, caster and model; 0 for an empty scan.
inline float beam_range_finder_model(const ScanBeams& z, const BeamBearings& bearings, const BeamReadings& readings,
                                     const Pose2& x, const Pose2& mount, const ConeRayCaster& cone,
                                     const BeamRangeFinderModel& model) {
  return beam_range_finder_model_over_bins(z, bearings, readings, x, mount, cone, model);
}
// The same over the packed table (4 bits per cell and heading): the same z*, half the memory.
inline float beam_range_finder_model(const ScanBeams& z, const BeamBearings& bearings, const BeamReadings& readings,
                                     const Pose2& x, const Pose2& mount, const PackedConeRayCaster& cone,
                                     const BeamRangeFinderModel& model) {
  return beam_range_finder_model_over_bins(z, bearings, readings, x, mount, cone, model);
}

}  // namespace est
