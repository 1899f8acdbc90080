#include "est/loop/beam_scan.hpp"
#include "est/loop/configured_loop.hpp"
#include "est/motion/holonomic_pose_model.hpp"
#include "est/random/samplers.hpp"
#include "est/util/trace.hpp"
#include "loop_digest.hpp"
#include "loop_world.hpp"
#include "selftest.hpp"

namespace est::selftest {
namespace {

using Beam = loop::BeamScan<GridRayCaster>;  // the beam model with exact ray casting: the board's path
constexpr std::uint32_t kParticles = 200;
using Configured =
    loop::ConfiguredLoop<loop::LoopConfig<HolonomicPoseMotionModel, loop::Filter::mcl, kParticles, kSmallScanBeams, 32u,
                                          2u, Beam>>;

}  // namespace

// The filter loop with the holonomic robot (est/motion/holonomic_pose_model.hpp) fed by its own input: twists
// (u_x, u_y) in the robot's frame at 50 Hz, through MCL with the beam model (Thrun table 6.1, z* ray cast exactly)
// on the small map's 10 Hz scans.
// The robot never turns: it stands at 0.5 rad and moves along its own x for 1 s, then sideways along its y for 1 s
// (the world sees both at an angle); the truth is the commanded displacement plus N(0, 2 mm) per 10 ms and axis.
void section_loop_holonomic(Trace& d) {
  const SmallMap world_map = small_map();
  Configured::EstimatorConfig cfg;
  cfg.control.noise_per_s = Eigen::Matrix2f::Identity() * 0.004f;
  cfg.control.heading_sigma_per_sqrt_s = 0.01f;
  cfg.beam_stride = 2;
  BeamModelParams beam;
  beam.range_max = 6.0f;
  beam.sigma_hit = 0.1f;
  static BeamRangeFinderModel beam_model;
  beam_model.configure(beam);
  StaticInstance<Configured::Estimator> estimator(cfg, 35u, Beam(world_map.caster, beam_model),
                                                  world_map.free_space);
  estimator->initialize_at({1.5f, 1.5f, 0.5f}, 0.1f, 0.05f, kParticles);
  StaticInstance<Configured::Loop> lp(*estimator, Configured::kTiming);

  LoopTraceSink sink{&d, 0u};
  LoopStepClock clock;
  Rng world(29u);
  Pose2 truth{1.5f, 1.5f, 0.5f};
  float held_x = 0.0f, held_y = 0.0f;  // the command of the last 20 ms
  float ranges[kSmallScanBeams];
  for (int k = 0; k <= 200; ++k) {
    const loop::TimeNs t = k * 10 * kMs;
    if (k > 0) {
      const Pose2 step{held_x * 0.01f + sample_normal(world, 0.002f), held_y * 0.01f + sample_normal(world, 0.002f),
                       0.0f};
      truth = compose(truth, step);
    }
    if (k % 2 == 0) {
      held_x = k < 100 ? 0.3f : 0.0f;
      held_y = k < 100 ? 0.0f : 0.3f;
      lp->push(loop::TwistInput{t, held_x, held_y, 0.0f});
    }
    if (k % 10 == 5) {
      simulate_small_scan(world_map.caster, truth, world, ranges);
      lp->push(loop::ScanInput{t, small_scan_layout(), ranges});
    }
    lp->run(clock, sink);
  }
  lp->flush(clock, sink);
  add_loop_end(d, sink.outputs, lp->counters(), truth,
               NamedCount{"resamplings", estimator->filter().counters().resamplings});
}

}  // namespace est::selftest
