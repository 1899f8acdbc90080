#include "est/loop/configured_loop.hpp"
#include "est/map/landmark_map.hpp"
#include "est/motion/diff_drive_model.hpp"
#include "est/random/samplers.hpp"
#include "est/util/trace.hpp"
#include "loop_digest.hpp"
#include "loop_world.hpp"
#include "selftest.hpp"

namespace est::selftest {
namespace {

struct LoopConfig {
  using Model = DiffDriveMotionModel;
  static constexpr loop::Filter kFilter = loop::Filter::ekf;
  static constexpr std::int32_t kMaxBeams = 1;  // scans are not used
  static constexpr std::uint32_t kQueueCapacity = 32;
  static constexpr std::uint32_t kScanSlots = 1;
  static constexpr loop::LoopTiming kTiming{};
};
using Configured = loop::ConfiguredLoop<LoopConfig>;

}  // namespace

// The filter loop with the EKF estimator (est/loop/ekf_estimator.hpp): a differential-drive robot's ticks (100 Hz)
// and landmark sightings (5 Hz, half with known correspondence, half by maximum likelihood, one outlier, one NaN, a
// few arriving late within the reorder window) to published estimates.
void section_loop_ekf(Trace& d) {
  Configured::EstimatorConfig cfg;
  cfg.motion.wheel_radius = 0.05f;
  cfg.motion.track_width = 0.3f;
  cfg.motion.ticks_per_rev = 1024u;
  cfg.motion.travel_sigma_per_m = 0.05f;
  cfg.motion.travel_sigma_floor = 0.0005f;
  cfg.motion.final_rot_sigma = 0.002f;
  cfg.ekf.additive_process_noise(2, 2) = 4.0e-6f;
  cfg.noise = {0.05f, 0.02f, 0.1f};
  Configured::Estimator estimator(cfg, LandmarkMap(kSmallLandmarks, kSmallLandmarkCount));
  estimator.initialize_at({1.0f, 1.0f, 0.0f}, 0.05f, 0.02f);
  Configured::Loop lp(estimator, Configured::kTiming);

  LoopTraceSink sink{&d, 0u};
  LoopStepClock clock;
  Rng world(9u);
  const float m_per_tick = diff_drive_m_per_tick(cfg.motion);
  Pose2 truth{1.0f, 1.0f, 0.0f};
  lp.push(loop::WheelTicksInput{0, {0, 0}, 2});
  loop::LandmarkInput late[6];
  std::int32_t n_late = 0;
  for (int k = 1; k <= 300; ++k) {  // 3 s: forward, then a left arc
    const float v = 0.5f, w = k > 100 ? 0.6f : 0.0f, dt = 0.01f;
    const float dl = (v - 0.5f * w * cfg.motion.track_width) * dt, dr = (v + 0.5f * w * cfg.motion.track_width) * dt;
    const std::int32_t tl = static_cast<std::int32_t>(dl / m_per_tick + 0.5f);
    const std::int32_t tr = static_cast<std::int32_t>(dr / m_per_tick + 0.5f);
    truth = DiffDriveMotionModel::sample(truth, {tl, tr}, cfg.motion, world);
    lp.push(loop::WheelTicksInput{k * 10 * kMs, {tl, tr}, 2});
    for (std::int32_t i = 0; i < n_late; ++i) lp.push(late[i]);  // one encoder period late
    n_late = 0;
    if (k % 20 == 10) {
      for (std::int32_t j = 0; j < 6; ++j) {
        const float dx = kSmallLandmarks[j].x - truth.x, dy = kSmallLandmarks[j].y - truth.y;
        loop::LandmarkInput z;
        z.t_ns = k * 10 * kMs;
        z.range_m = fmath::sqrt(dx * dx + dy * dy) + sample_normal(world, 0.05f);
        z.bearing_rad = fmath::normalize_angle(fmath::atan2(dy, dx) - truth.theta + sample_normal(world, 0.02f));
        z.signature = kSmallLandmarks[j].signature + sample_normal(world, 0.1f);
        z.id = (k / 20 + j) % 2 == 0 ? j : -1;
        if (k == 110 && j == 1) z.range_m += 3.0f;           // an outlier the gate refuses
        if (k == 150 && j == 2) z.range_m = __builtin_nanf("");  // a bad reading
        if (j >= 4)
          late[n_late++] = z;
        else
          lp.push(z);
      }
    }
    lp.run(clock, sink);
  }
  lp.flush(clock, sink);
  const loop::LoopCounters& c = lp.counters();
  const CorrectionCounters& r = estimator.filter().counters();
  d.step(sink.outputs);
  d.add_u32("outputs", sink.outputs);
  d.add_u32("predictions", c.predictions);
  d.add_u32("corrections", c.corrections);
  d.add_u32("rejected", c.rejected);
  d.add_u32("too_old", c.too_old);
  d.add_u32("accepted", r.accepted);
  d.add_u32("gated_out", r.gated_out);
  d.add_u32("nonfinite", r.nonfinite);
  d.add("truth_x", truth.x);
  d.add("truth_y", truth.y);
}

}  // namespace est::selftest
