#include "est/loop/configured_loop.hpp"
#include "est/motion/odometry_model.hpp"
#include "est/motion/velocity_model.hpp"
#include "est/util/trace.hpp"
#include "loop_digest.hpp"
#include "loop_world.hpp"
#include "selftest.hpp"

namespace est::selftest {
namespace {

constexpr std::uint32_t kParticles = 200;
using Configured =
    loop::ConfiguredLoop<loop::LoopConfig<OdometryMotionModel, loop::Filter::mcl, kParticles, kSmallScanBeams, 32u,
                                          2u>>;

}  // namespace

// The filter loop with the odometry model (Thrun table 5.6) fed by its own input: odometry increments at 100 Hz from
// a base whose odometry overestimates its travel by 3 % and underestimates its turns by 4 % (so its frame drifts
// from the world), through MCL with the likelihood field on the small map's 10 Hz scans. Each scan is stamped
// halfway between two increments: the loop splits the next increment at the scan's time.
void section_loop_odometry(Trace& d) {
  const SmallMap world_map = small_map();
  Configured::EstimatorConfig cfg;
  cfg.motion = {0.02f, 0.02f, 0.02f, 0.002f, 1.0e-4f};
  cfg.beam_stride = 2;
  StaticInstance<Configured::Estimator> estimator(cfg, 31u, loop::LikelihoodFieldScan(world_map.field),
                                                  world_map.free_space);
  estimator->initialize_at({1.0f, 1.0f, 0.0f}, 0.1f, 0.05f, kParticles);
  StaticInstance<Configured::Loop> lp(*estimator, Configured::kTiming);

  LoopTraceSink sink{&d, 0u};
  LoopStepClock clock;
  Rng world(23u);
  VelocityParams arc;
  arc.dt = 0.01f;
  VelocityParams half = arc;
  half.dt = 0.005f;
  Pose2 truth{1.0f, 1.0f, 0.0f};
  Pose2 odom{3.0f, -2.0f, 1.0f};  // the odometry frame's own origin
  float ranges[kSmallScanBeams];
  for (int k = 1; k <= 200; ++k) {  // 2 s: forward, then a left arc
    const float v = 0.5f, w = k > 100 ? 0.6f : 0.0f;
    const Pose2 before = truth;
    truth = VelocityMotionModel::predict(truth, {v, w}, arc);
    const Pose2 odom_next = VelocityMotionModel::predict(odom, {1.03f * v, 0.96f * w}, arc);
    const loop::OdometryInput increment{k * 10 * kMs, between(odom, odom_next)};
    odom = odom_next;
    lp->push(increment);
    if (k % 10 == 0) {  // the scan of 5 ms ago arrives with this increment
      simulate_small_scan(world_map.caster, VelocityMotionModel::predict(before, {v, w}, half), world, ranges);
      lp->push(loop::ScanInput{k * 10 * kMs - 5 * kMs, small_scan_layout(), ranges});
    }
    lp->run(clock, sink);
  }
  lp->flush(clock, sink);
  add_loop_end(d, sink.outputs, lp->counters(), truth,
               NamedCount{"resamplings", estimator->filter().counters().resamplings});
}

}  // namespace est::selftest
