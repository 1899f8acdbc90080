#pragma once
// bench-mcl's beam_density phase: the beam model's density and product alone, what is left of it when z* is given.
// A translation unit of its own: in bench_mcl_main.cpp the extra call sites changed GCC's inlining of the beam
// model's own loop (add_hit out of line: +2 % on the phases it was to be compared with).
#include <cstdint>

#include "est/filter/particle_set.hpp"
#include "est/map/cone_ray_caster.hpp"
#include "est/sensor/beam_range_finder_model.hpp"
#include "est/sensor/beam_readings.hpp"
#include "est/sensor/range_scan.hpp"

namespace board {

// Instructions to take table 6.1's density of every particle-beam at its z* (cast by `cone` from the particle's
// sensor pose before counting, into z_exp[count * z.count]) and the product of each particle's densities to log
// space, as the beam model does; the logs are added to sink.
std::uint64_t count_beam_density(const est::ScanBeams& z, const est::BeamReadings& readings,
                                 est::ConstParticleSetView p, const est::Pose2& mount, const est::ConeRayCaster& cone,
                                 const est::BeamRangeFinderModel& model, float* z_exp, volatile float& sink);

}  // namespace board
