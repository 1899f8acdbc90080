// reference-ekf.elf: the reference EKF localization rig on the board, for its budgets (instructions per loop step,
// stack, and through the image's size its RAM and flash): a differential drive localized by the EKF (Thrun table
// 7.2, and 7.3 where the sensor gives no correspondence) on 32 landmarks (a 4 x 8 grid, 1.25 m apart), the loop's
// queue of 64 inputs.
//
// The workload (reference_step() is the loop's run() after each push):
//  - typical: 3 s of a route, encoder ticks at 100 Hz and, at 5 Hz, a sighting of every landmark within 3 m (half
//    with the sensor's correspondence, half without); the steps that corrected and those that only predicted apart;
//  - the worst step: one run() after every landmark was sighted at once without correspondence (32 features, each
//    associated by maximum likelihood over the 32 landmarks) following a gap of 1 s in the inputs (the loop's
//    longest catch-up, 100 predictions).
// Prints the figures, then "budget KEY VALUE UNIT" lines for check_budgets.cmake, then PASS, or FAIL when the
// estimate did not track the route.
#include <cstdint>

#include "est/loop/configured_loop.hpp"
#include "est/map/landmark_map.hpp"
#include "est/math/fmath.hpp"
#include "est/motion/diff_drive_model.hpp"
#include "reference_step.hpp"
#include "stack_paint.hpp"
#include "static_object.hpp"

namespace {

struct Config {
  using Model = est::DiffDriveMotionModel;
  static constexpr est::loop::Filter kFilter = est::loop::Filter::ekf;
  static constexpr std::int32_t kMaxBeams = 1;  // no scans
  static constexpr std::uint32_t kQueueCapacity = 64;
  static constexpr std::uint32_t kScanSlots = 1;
  static constexpr est::loop::LoopTiming kTiming{};
};
using Rig = est::loop::ConfiguredLoop<Config>;
using est::loop::TimeNs;

constexpr std::int32_t kLandmarks = 32;
constexpr TimeNs kMs = 1000000;

est::Landmark g_landmarks[kLandmarks];
board::Static<Rig::Estimator> g_estimator;
board::Static<Rig::Loop> g_loop;
Rig::Loop* g_lp = nullptr;

struct StepClock {  // the loop reads time only to time its steps
  TimeNs t = 0;
  TimeNs operator()() { return t += 1000; }
};
struct LastEstimate {
  est::loop::LoopOutput last{};
  std::uint32_t outputs = 0;
  void operator()(const est::loop::LoopOutput& o) {
    last = o;
    ++outputs;
  }
};
StepClock g_clock;
LastEstimate g_sink;

// The feature of landmark j seen from `truth` (small fixed offsets for noise), with its id or without.
est::loop::LandmarkInput sighting(TimeNs t, const est::Pose2& truth, std::int32_t j, bool with_id) {
  const float dx = g_landmarks[j].x - truth.x, dy = g_landmarks[j].y - truth.y;
  est::loop::LandmarkInput z;
  z.t_ns = t;
  z.range_m = est::fmath::sqrt(dx * dx + dy * dy) + 0.01f * static_cast<float>(j % 3 - 1);
  z.bearing_rad = est::fmath::normalize_angle(est::fmath::atan2(dy, dx) - truth.theta + 0.002f);
  z.signature = g_landmarks[j].signature;
  z.id = with_id ? j : -1;
  return z;
}

}  // namespace

extern "C" __attribute__((noinline)) void reference_step() { g_lp->run(g_clock, g_sink); }

int main() {
  for (std::int32_t j = 0; j < kLandmarks; ++j)
    g_landmarks[j] = {0.5f + 1.25f * static_cast<float>(j % 8), 0.5f + 1.25f * static_cast<float>(j / 8),
                      static_cast<float>(j % 5)};
  Rig::EstimatorConfig config;
  config.motion = est::DiffDriveParams{0.05f, 0.3f, 4096u, 0.05f, 0.0005f, 0.002f};
  config.ekf.additive_process_noise(2, 2) = 4.0e-6f;
  config.noise = {0.05f, 0.02f, 0.1f};
  est::Pose2 truth{1.0f, 1.0f, 0.0f};
  Rig::Estimator& estimator = g_estimator.emplace(config, est::LandmarkMap(g_landmarks, kLandmarks));
  estimator.initialize_at(truth, 0.05f, 0.02f);
  g_lp = &g_loop.emplace(estimator, Rig::kTiming);

  const float m_per_tick = est::kTwoPi * config.motion.wheel_radius / static_cast<float>(config.motion.ticks_per_rev);
  TimeNs t = 0;
  std::int32_t k = 0;
  const auto ticks_of = [&](TimeNs dt_ns) {  // the route: straight for 1 s, then an arc
    ++k;
    t += dt_ns;
    const float dt = static_cast<float>(dt_ns) * 1e-9f;
    const float v = 0.5f, w = k > 100 ? 0.4f : 0.0f, b = config.motion.track_width;
    const std::int32_t tl = static_cast<std::int32_t>((v - 0.5f * w * b) * dt / m_per_tick + 0.5f);
    const std::int32_t tr = static_cast<std::int32_t>((v + 0.5f * w * b) * dt / m_per_tick + 0.5f);
    truth = est::DiffDriveMotionModel::predict(truth, {tl, tr}, config.motion);
    return est::loop::WheelTicksInput{t, {tl, tr}, 2};
  };

  board::StepCounts correct, predict;
  bool pushed = true;
  std::uint32_t sighted = 0;
  board::stack_paint();
  for (int i = 1; i <= 300; ++i) {
    pushed = g_lp->push(ticks_of(10 * kMs)) && pushed;
    if (i % 20 == 0)
      for (std::int32_t j = 0; j < kLandmarks; ++j) {
        const float dx = g_landmarks[j].x - truth.x, dy = g_landmarks[j].y - truth.y;
        if (dx * dx + dy * dy > 9.0f) continue;
        pushed = g_lp->push(sighting(t, truth, j, j % 2 == 0)) && pushed;
        ++sighted;
      }
    const std::uint32_t corrections = g_lp->counters().corrections;
    const std::uint64_t n = board::counted_step();
    (g_lp->counters().corrections != corrections ? correct : predict).add(n);
  }
  for (int i = 0; i < 3; ++i) {  // the last sightings of the route applied
    pushed = g_lp->push(ticks_of(10 * kMs)) && pushed;
    board::counted_step();
  }
  // The worst step: after a gap of 1 s, every landmark at once, without correspondence.
  const std::uint32_t predictions = g_lp->counters().predictions, corrections = g_lp->counters().corrections;
  pushed = g_lp->push(ticks_of(1000 * kMs)) && pushed;
  for (std::int32_t j = 0; j < kLandmarks; ++j) pushed = g_lp->push(sighting(t, truth, j, false)) && pushed;
  pushed = g_lp->push(ticks_of(30 * kMs)) && pushed;
  const std::uint64_t worst = board::counted_step();
  const std::uint32_t worst_predictions = g_lp->counters().predictions - predictions;
  const std::uint32_t worst_corrections = g_lp->counters().corrections - corrections;
  for (int i = 0; i < 20; ++i) {
    pushed = g_lp->push(ticks_of(10 * kMs)) && pushed;
    board::counted_step();
  }
  const std::uint32_t stack = board::stack_high_water();
  g_lp->flush(g_clock, g_sink);

  board::write("reference-ekf: ");
  board::write_dec(sighted);
  board::write(" sightings on the route\n");
  board::write_counts("reference-ekf", "typical steps with landmark corrections", correct);
  board::write_counts("reference-ekf", "typical steps that only predict", predict);
  board::write("reference-ekf: the worst step (every landmark without correspondence after a gap of 1 s: ");
  board::write_dec(worst_predictions);
  board::write(" predictions, ");
  board::write_dec(worst_corrections);
  board::write(" corrections): ");
  board::write_dec(worst);
  board::write(" instructions\nreference-ekf: stack of a step (painted): ");
  board::write_dec(stack);
  board::write(" bytes\n");
  board::report_budget("ekf.step.correct", correct.mean(), "instructions");
  board::report_budget("ekf.step.predict", predict.mean(), "instructions");
  board::report_budget("ekf.step.worst", worst, "instructions");
  board::report_budget("ekf.stack.step", stack, "bytes");

  const est::Pose2 e = g_sink.last.estimate.mean;
  const float dx = e.x - truth.x, dy = e.y - truth.y;
  const bool tracked = g_sink.outputs > 0u && dx * dx + dy * dy < 0.04f;
  const bool ok = pushed && tracked && correct.steps >= 14u && worst_predictions >= 100u &&
                  worst_corrections == static_cast<std::uint32_t>(kLandmarks) && stack < board::kStackPaintWindow;
  board::write(ok ? "reference-ekf: PASS\n" : "reference-ekf: FAIL (the workload went wrong)\n");
  return ok ? 0 : 1;
}
