#include "est/loop/configured_loop.hpp"
#include "est/motion/omni_model.hpp"
#include "est/motion/omni_wheels.hpp"
#include "est/util/trace.hpp"
#include "loop_digest.hpp"
#include "loop_world.hpp"
#include "selftest.hpp"

namespace est::selftest {
namespace {

using Configured =  // scans are not used
    loop::ConfiguredLoop<loop::LoopConfig<OmniMotionModel, loop::Filter::ekf, 0u, 1, 32u, 1u>>;
using Source = loop::ControlAssembler<OmniMotionModel>::Source;

constexpr float kMetresPerTick = 0.0005f;

std::int32_t round_to_int(float v) {
  return v >= 0.0f ? static_cast<std::int32_t>(v + 0.5f) : -static_cast<std::int32_t>(-v + 0.5f);
}

}  // namespace

// The filter loop with the omnidirectional model fed by its own inputs: the encoders of four mecanum wheels (X
// arrangement, 0.2 m half wheelbase and half track) at 100 Hz, whose least-squares body displacement is the twist
// (est/motion/omni_wheels.hpp); the EKF corrects with landmark sightings at 5 Hz. The base drives forward, then
// sideways (pure v2), then diagonally while turning, 1 s each; its true motion is sampled from the same model and
// the encoders see the wheels' travel of each true step.
void section_loop_omni(Trace& d) {
  Configured::EstimatorConfig cfg;
  cfg.motion = {{0.05f, 0.01f, 0.01f, 0.01f, 0.05f, 0.01f, 0.05f, 0.05f, 0.05f}, 0.01f};
  float rows[4][3] = {};
  mecanum_wheel_rows(0.2f, 0.2f, rows);
  cfg.control.source = Source::wheels;
  configure_omni_wheels(cfg.control.wheels, rows, 4, kMetresPerTick);
  cfg.ekf.additive_process_noise(2, 2) = 4.0e-6f;
  cfg.noise = {0.05f, 0.02f, 0.1f};
  Configured::Estimator estimator(cfg, LandmarkMap(kSmallLandmarks, kSmallLandmarkCount));
  estimator.initialize_at({1.0f, 1.0f, 0.0f}, 0.05f, 0.02f);
  Configured::Loop lp(estimator, Configured::kTiming);

  LoopTraceSink sink{&d, 0u};
  LoopStepClock clock;
  Rng world(27u);
  OmniParams truth_noise = cfg.motion;
  for (float& a : truth_noise.alpha) a *= 0.2f;
  Pose2 truth{1.0f, 1.0f, 0.0f};
  float travel_m[4] = {};  // of each wheel, for ticks without drift
  std::int32_t ticks_sent[4] = {};
  loop::LandmarkInput sighting[kSmallLandmarkCount];
  for (int k = 0; k <= 300; ++k) {
    const loop::TimeNs t = k * 10 * kMs;
    loop::WheelTicksInput ticks{t, {}, 4};
    if (k > 0) {
      const OmniControl u = k <= 100 ? OmniControl{0.3f, 0.0f, 0.0f}
                                     : (k <= 200 ? OmniControl{0.0f, 0.3f, 0.0f} : OmniControl{0.2f, -0.2f, 0.4f});
      // The true control of this step, held for 10 ms: the wheels roll J (v1, v2, w) dt.
      const Pose2 before = truth;
      truth = OmniMotionModel::sample(truth, u, truth_noise, world);
      const float turn = fmath::normalize_angle(truth.theta - before.theta);
      const Pose2 body = between(before, truth);
      for (int i = 0; i < 4; ++i) {
        travel_m[i] += rows[i][0] * body.x + rows[i][1] * body.y + rows[i][2] * turn;
        const std::int32_t total = round_to_int(travel_m[i] / kMetresPerTick);
        ticks.ticks[i] = total - ticks_sent[i];
        ticks_sent[i] = total;
      }
    }
    lp.push(ticks);
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
