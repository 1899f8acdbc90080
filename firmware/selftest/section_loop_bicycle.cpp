#include "est/loop/configured_loop.hpp"
#include "est/loop/steered_scan.hpp"
#include "est/motion/bicycle_model.hpp"
#include "est/random/samplers.hpp"
#include "est/util/trace.hpp"
#include "loop_digest.hpp"
#include "loop_world.hpp"
#include "selftest.hpp"

namespace est::selftest {
namespace {

constexpr std::uint32_t kParticles = 200;
template <typename Scan>
using Configured = loop::ConfiguredLoop<
    loop::LoopConfig<BicycleMotionModel, loop::Filter::mcl, kParticles, kSmallScanBeams, 32u, 2u, Scan>>;

constexpr float kMetresPerTick = 0.0005f;

template <typename Scan>
void run_bicycle_loop(Trace& d, const SmallMap& world_map, const Scan& scan_model, const SteeredMount* handlebar);

}  // namespace

// The filter loop with the bicycle model (front-wheel referenced) fed by its own inputs: the front wheel's traction
// encoder at 100 Hz and the steering sensor at 50 Hz (sample and hold), through MCL with the likelihood field on the
// small map's 10 Hz scans, stamped 3 ms before the encoder sample they arrive with (the loop splits its ticks). The
// bicycle runs straight for 1 s, then steers 0.35 rad left for 1 s; its true motion is sampled from the same model.
void section_loop_bicycle(Trace& d) {
  const SmallMap world_map = small_map();
  run_bicycle_loop(d, world_map, loop::LikelihoodFieldScan(world_map.field), nullptr);
}

// The same bicycle with its rangefinder on the handlebar (0.15 m ahead of the steering axis at the front wheel, so
// the sensor's pose follows the steering), through MCL with the steered model marginalizing six handle positions
// with the steering readings (est/loop/steered_scan.hpp).
void section_loop_steered(Trace& d) {
  const SmallMap world_map = small_map();
  loop::SteeredScanConfig steered;
  steered.mount.pivot_x = 0.4f;
  steered.mount.sensor_on_part = Pose2{0.15f, 0.0f, 0.0f};
  steered.steer_max = 1.0471976f;
  run_bicycle_loop(d, world_map, loop::SteeredScan<kParticles>(world_map.field, steered), &steered.mount);
}

namespace {

template <typename Scan>
void run_bicycle_loop(Trace& d, const SmallMap& world_map, const Scan& scan_model, const SteeredMount* handlebar) {
  using Loop = Configured<Scan>;
  typename Loop::EstimatorConfig cfg;
  cfg.motion = {0.4f, 1.0471976f, 0.02f, 0.05f, 0.005f, 0.01f};  // l 0.4 m, stops at 60 deg
  cfg.control.metres_per_tick = kMetresPerTick;
  cfg.beam_stride = 2;
  StaticInstance<typename Loop::Estimator> estimator(cfg, 33u, scan_model, world_map.free_space);
  estimator->initialize_at({1.0f, 1.0f, 0.0f}, 0.1f, 0.05f, kParticles);
  StaticInstance<typename Loop::Loop> lp(*estimator, Loop::kTiming);

  LoopTraceSink sink{&d, 0u};
  LoopStepClock clock;
  Rng world(25u);
  BicycleParams truth_noise = cfg.motion;
  truth_noise.steer_sigma = 0.005f;
  truth_noise.speed_var_per_speed = 0.005f;
  truth_noise.final_rot_sigma = 0.001f;
  Pose2 truth{1.0f, 1.0f, 0.0f};
  float travel_m = 0.0f;  // of the front wheel, for ticks without drift
  std::int32_t ticks_sent = 0;
  float ranges[kSmallScanBeams];
  for (int k = 0; k <= 200; ++k) {
    const loop::TimeNs t = k * 10 * kMs;
    const float steer = k > 100 ? 0.35f : 0.0f;
    std::int32_t ticks = 0;
    if (k > 0) {
      const Pose2 before = truth;
      truth = BicycleMotionModel::sample(truth, {0.5f, steer}, truth_noise, world);
      const float dx = truth.x - before.x, dy = truth.y - before.y;
      travel_m += fmath::sqrt(dx * dx + dy * dy);
      const std::int32_t total = static_cast<std::int32_t>(travel_m / kMetresPerTick + 0.5f);
      ticks = total - ticks_sent;
      ticks_sent = total;
    }
    lp->push(loop::WheelTicksInput{t, {ticks}, 1});
    if (k % 2 == 0) lp->push(loop::SteeringInput{t, steer + sample_normal(world, 0.005f)});
    if (k % 10 == 5) {
      const Pose2 sensor = handlebar != nullptr ? compose(truth, steered_sensor_mount(*handlebar, steer)) : truth;
      simulate_small_scan(world_map.caster, sensor, world, ranges);
      lp->push(loop::ScanInput{t - 3 * kMs, small_scan_layout(), ranges});
    }
    lp->run(clock, sink);
  }
  lp->flush(clock, sink);
  add_loop_end(d, sink.outputs, lp->counters(), truth,
               NamedCount{"resamplings", estimator->filter().counters().resamplings});
}

}  // namespace

}  // namespace est::selftest
