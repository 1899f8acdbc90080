#include "est/loop/configured_loop.hpp"
#include "est/motion/velocity_model.hpp"
#include "est/util/trace.hpp"
#include "loop_digest.hpp"
#include "loop_world.hpp"
#include "selftest.hpp"

namespace est::selftest {
namespace {

using Configured =  // scans are not used
    loop::ConfiguredLoop<loop::LoopConfig<VelocityMotionModel, loop::Filter::ekf, 0u, 1, 32u, 1u>>;

}  // namespace

// The filter loop with the velocity model (Thrun table 5.3) fed by its own input: commanded twists (v, w) at 50 Hz,
// held and averaged over each 100 Hz prediction, a sideways speed in them that the model ignores; the EKF corrects
// with landmark sightings at 5 Hz (known correspondence every other sighting, maximum likelihood otherwise). The
// robot runs straight, turns left, then right, for 3 s, its true motion sampled from the same model.
void section_loop_velocity(Trace& d) {
  Configured::EstimatorConfig cfg;
  cfg.motion = {0.02f, 0.002f, 0.02f, 0.02f, 0.0005f, 0.0005f, 0.01f};
  cfg.ekf.additive_process_noise(2, 2) = 4.0e-6f;
  cfg.noise = {0.05f, 0.02f, 0.1f};
  Configured::Estimator estimator(cfg, LandmarkMap(kSmallLandmarks, kSmallLandmarkCount));
  estimator.initialize_at({1.0f, 1.0f, 0.0f}, 0.05f, 0.02f);
  Configured::Loop lp(estimator, Configured::kTiming);

  LoopTraceSink sink{&d, 0u};
  LoopStepClock clock;
  Rng world(21u);
  VelocityParams truth_noise = cfg.motion;
  truth_noise.a1 = truth_noise.a3 = 0.005f;
  Pose2 truth{1.0f, 1.0f, 0.0f};
  loop::LandmarkInput sighting[kSmallLandmarkCount];
  VelocityControl held;  // the command of the last 20 ms
  for (int k = 0; k <= 300; ++k) {
    if (k > 0) truth = VelocityMotionModel::sample(truth, held, truth_noise, world);
    const loop::TimeNs t = k * 10 * kMs;
    if (k % 2 == 0) {
      held = {0.4f, k < 100 ? 0.0f : (k < 200 ? 0.5f : -0.3f)};
      lp.push(loop::TwistInput{t, held.v, 0.05f, held.w});
    }
    if (k % 20 == 10) {
      sight_small_landmarks(truth, t, (k / 20) % 2 == 0, world, sighting);
      for (const loop::LandmarkInput& z : sighting) lp.push(z);
    }
    lp.run(clock, sink);
  }
  lp.flush(clock, sink);
  const CorrectionCounters& r = estimator.filter().counters();
  add_loop_end(d, sink.outputs, lp.counters(), truth, NamedCount{"accepted", r.accepted},
               NamedCount{"gated_out", r.gated_out});
}

}  // namespace est::selftest
