#include "bench_beam_density.hpp"

#include "est/math/log_product.hpp"
#include "instruction_counter.hpp"

namespace board {

std::uint64_t count_beam_density(const est::ScanBeams& z, const est::BeamReadings& readings,
                                 est::ConstParticleSetView p, const est::Pose2& mount, const est::ConeRayCaster& cone,
                                 const est::BeamRangeFinderModel& model, float* z_exp, volatile float& sink) {
  const std::uint32_t k_count = static_cast<std::uint32_t>(z.count);
  for (std::uint32_t i = 0; i < p.count; ++i) {
    const est::SensorFrame f = est::sensor_frame(p.pose(i), mount);
    for (std::uint32_t k = 0; k < k_count; ++k) {
      float dx = 0.0f, dy = 0.0f;
      f.beam(z, static_cast<std::int32_t>(k), dx, dy);
      z_exp[i * k_count + k] = cone.cast(f.x, f.y, dx, dy, model.params().range_max);
    }
  }
  instruction_counter_start();
  for (std::uint32_t i = 0; i < p.count; ++i) {
    est::LogProduct q;
    for (std::uint32_t k = 0; k < k_count; ++k) q.mul(model.density(readings.reading[k], z_exp[i * k_count + k]));
    sink = sink + q.log();
  }
  return instruction_counter_read();
}

}  // namespace board
