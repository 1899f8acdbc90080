#include "est/filter/free_space_sampler.hpp"
#include "est/loop/configured_loop.hpp"
#include "est/motion/diff_drive_model.hpp"
#include "est/random/samplers.hpp"
#include "est/util/trace.hpp"
#include "loop_digest.hpp"
#include "loop_world.hpp"
#include "selftest.hpp"

namespace est::selftest {
namespace {

// The firmware's configuration, as a board would state it.
struct LoopConfig {
  using Model = DiffDriveMotionModel;
  static constexpr loop::Filter kFilter = loop::Filter::mcl;
  static constexpr std::uint32_t kMaxParticles = 256;
  static constexpr std::int32_t kMaxBeams = 60;
  static constexpr std::uint32_t kQueueCapacity = 32;
  static constexpr std::uint32_t kScanSlots = 2;
  static constexpr loop::LoopTiming kTiming{};  // 100 Hz predictions, 20 ms reorder window, default limits
};
using Configured = loop::ConfiguredLoop<LoopConfig>;
using Estimator = Configured::Estimator;
using Loop = Configured::Loop;

}  // namespace

// The filter loop end to end (est/loop): a differential-drive robot's encoder ticks (100 Hz) and 60-beam scans
// (10 Hz) pushed with a few late arrivals, through MclEstimator with the likelihood field, to published estimates.
void section_loop(Trace& d) {
  const SmallMap world_map = small_map();
  const FreeSpaceSampler& free_space = world_map.free_space;
  const GridRayCaster& caster = world_map.caster;

  Configured::EstimatorConfig cfg;
  cfg.motion.wheel_radius = 0.05f;
  cfg.motion.track_width = 0.3f;
  cfg.motion.ticks_per_rev = 1024u;
  cfg.motion.travel_sigma_per_m = 0.05f;
  cfg.motion.travel_sigma_floor = 0.001f;
  cfg.motion.final_rot_sigma = 0.005f;
  cfg.beam_stride = 2;
  // Locals (~60 KiB of stack): the estimator and the loop hold references, and every run starts afresh.
  Estimator estimator(cfg, 77u, loop::LikelihoodFieldScan(world_map.field), free_space);
  estimator.initialize_at({1.0f, 1.0f, 0.0f}, 0.1f, 0.05f, 256u);
  Loop lp(estimator, Configured::kTiming);

  LoopTraceSink sink{&d, 0u};
  LoopStepClock clock;
  Rng world(5u);
  const float m_per_tick = kTwoPi * cfg.motion.wheel_radius / static_cast<float>(cfg.motion.ticks_per_rev);
  Pose2 truth{1.0f, 1.0f, 0.0f};
  float ranges[kSmallScanBeams];
  for (int k = 1; k <= 200; ++k) {  // 2 s: forward, then a left arc
    const float v = 0.5f, w = k > 100 ? 0.6f : 0.0f, dt = 0.01f;
    const float dl = (v - 0.5f * w * cfg.motion.track_width) * dt, dr = (v + 0.5f * w * cfg.motion.track_width) * dt;
    const std::int32_t tl = static_cast<std::int32_t>(dl / m_per_tick + 0.5f);
    const std::int32_t tr = static_cast<std::int32_t>(dr / m_per_tick + 0.5f);
    truth = DiffDriveMotionModel::predict(truth, {tl, tr}, cfg.motion);
    const loop::WheelTicksInput ticks{k * 10 * kMs, {tl, tr}, 2};
    if (k % 10 == 5) {  // a scan at 10 Hz, pushed after the next encoder sample: arrives late, within the window
      simulate_small_scan(caster, truth, world, ranges);
      ranges[7] = __builtin_nanf("");  // a bad reading the scan preparation rejects and counts
      const loop::ScanInput scan{k * 10 * kMs - 3 * kMs, small_scan_layout(), ranges};
      lp.push(ticks);
      lp.push(scan);
    } else {
      lp.push(ticks);
    }
    lp.run(clock, sink);
  }
  lp.flush(clock, sink);
  const loop::LoopCounters& c = lp.counters();
  d.step(sink.outputs);
  d.add_u32("outputs", sink.outputs);
  d.add_u32("predictions", c.predictions);
  d.add_u32("corrections", c.corrections);
  d.add_u32("rejected", c.rejected);
  d.add_u32("too_old", c.too_old);
  d.add("truth_x", truth.x);
  d.add("truth_y", truth.y);
}

}  // namespace est::selftest
