// reference-mcl.elf: the reference MCL rig on the board, for its budgets (instructions per loop step, stack, and
// through the image's size its RAM and flash): a differential drive localized by augmented MCL with the likelihood
// field, 512 particles (no KLD: every step moves all of them), a 360-beam scan of which every 6th beam is used
// (K = 60), in a 200 x 200 map at 0.05 m (a 10 m room with walls and furniture, built in the image), the loop's
// queue of 32 inputs and 2 scan slots.
//
// The workload (reference_step() is the loop's run() after each push):
//  - typical: 3 s of a route, encoder ticks at 100 Hz and scans at 10 Hz; the steps that corrected with a scan
//    and the steps that only predicted, counted apart;
//  - a scan with every beam at max range;
//  - the worst step: one run() that applies a full queue, after a gap of 1 s in the inputs (the loop's longest
//    catch-up, 100 predictions, LoopTiming::max_catch_up_predictions), 29 encoder samples and both scan slots (one
//    scan at max range), every particle moved and weighed.
// Prints the figures, then "budget KEY VALUE UNIT" lines for check_budgets.cmake, then PASS, or FAIL when the
// estimate did not track the route (a workload that went wrong measures nothing).
#include <cstdint>

#include "est/filter/free_space_sampler.hpp"
#include "est/loop/configured_loop.hpp"
#include "est/map/distance_transform.hpp"
#include "est/map/occupancy_grid.hpp"
#include "est/map/ray_casting.hpp"
#include "est/math/fmath.hpp"
#include "est/motion/diff_drive_model.hpp"
#include "est/sensor/likelihood_field_grid.hpp"
#include "est/sensor/likelihood_field_range_finder_model.hpp"
#include "reference_step.hpp"
#include "stack_paint.hpp"
#include "static_object.hpp"

namespace {

struct Config {
  using Model = est::DiffDriveMotionModel;
  static constexpr est::loop::Filter kFilter = est::loop::Filter::mcl;
  using ScanModel = est::loop::LikelihoodFieldScan;
  static constexpr std::uint32_t kMaxParticles = 512;
  static constexpr std::int32_t kMaxBeams = 360;
  static constexpr std::uint32_t kQueueCapacity = 32;
  static constexpr std::uint32_t kScanSlots = 2;
  static constexpr est::loop::LoopTiming kTiming{};
};
using Rig = est::loop::ConfiguredLoop<Config>;
using est::loop::TimeNs;

constexpr std::int32_t kSide = 200;
constexpr float kResolution = 0.05f;
constexpr std::int32_t kBeams = 360;
constexpr TimeNs kMs = 1000000;
constexpr float kRangeMax = 8.0f;

est::OccupancyGridStorage<kSide, kSide> g_grid;
est::DistanceTransformStorage<kSide, kSide> g_edt;
est::LikelihoodFieldGridStorage<kSide, kSide> g_field_grid;
est::LikelihoodField g_field;
board::Static<Rig::Estimator> g_estimator;
board::Static<Rig::Loop> g_loop;
Rig::Loop* g_lp = nullptr;
float g_ranges[3][kBeams];  // the scans in the queue at once (two slots) and the next one

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

// The room: walls round it, a wall with a door, two tables and a pillar.
void build_room() {
  g_grid.configure(kSide, kSide, kResolution, 0.0f, 0.0f, est::kFreeCell);
  const std::uint8_t o = est::kOccupiedCell;
  g_grid.fill_rect(0, 0, kSide - 1, 1, o);
  g_grid.fill_rect(0, kSide - 2, kSide - 1, kSide - 1, o);
  g_grid.fill_rect(0, 0, 1, kSide - 1, o);
  g_grid.fill_rect(kSide - 2, 0, kSide - 1, kSide - 1, o);
  g_grid.fill_rect(120, 0, 121, 90, o);
  g_grid.fill_rect(120, 120, 121, kSide - 1, o);
  g_grid.fill_rect(30, 140, 70, 160, o);
  g_grid.fill_rect(150, 30, 175, 60, o);
  g_grid.fill_rect(60, 100, 66, 106, o);
}

// 360 beams from `truth` by exact casting, 1 cm of quantization noise, at most the max range.
void scan_from(const est::DistanceTransformRayCaster& caster, const est::Pose2& truth, float* ranges) {
  for (std::int32_t k = 0; k < kBeams; ++k) {
    float s = 0.0f, c = 0.0f;
    est::fmath::sincos(truth.theta - est::kPi + static_cast<float>(k) * (est::kTwoPi / kBeams), s, c);
    const float z = caster.cast(truth.x, truth.y, c, s, kRangeMax) + 0.01f * static_cast<float>(k % 3 - 1);
    ranges[k] = z < kRangeMax ? z : kRangeMax;
  }
}

constexpr est::ScanLayout kLayout{-est::kPi, est::kTwoPi / kBeams, kBeams, 0.05f, kRangeMax};

}  // namespace


extern "C" __attribute__((noinline)) void reference_step() { g_lp->run(g_clock, g_sink); }

int main() {
  build_room();
  const est::OccupancyGrid grid = g_grid.grid();
  if (g_edt.build(grid) != est::MapStatus::ok) return board::write("reference-mcl: FAIL distance transform\n"), 1;
  const est::LikelihoodFieldParams params{0.85f, 0.05f, 0.10f, 0.2f, kRangeMax, 2.0f};
  if (g_field.configure(params, grid, g_edt.view()) != est::SensorModelStatus::ok ||
      g_field_grid.build(g_field, grid) != est::MapStatus::ok)
    return board::write("reference-mcl: FAIL likelihood field\n"), 1;
  const est::LikelihoodFieldGrid field_grid = g_field_grid.view();
  const est::FreeSpaceSampler free_space(grid, g_edt.view(), 0.2f);
  const est::DistanceTransformRayCaster caster(grid, g_edt.view());

  Rig::EstimatorConfig config;
  config.motion = est::DiffDriveParams{0.05f, 0.3f, 4096u, 0.05f, 0.003f, 0.01f};
  config.beam_stride = 6;
  est::Pose2 truth{2.0f, 2.0f, 0.0f};
  Rig::Estimator& estimator =
      g_estimator.emplace(config, 11u, est::loop::LikelihoodFieldScan(g_field, est::Pose2{}, &field_grid), free_space);
  estimator.initialize_at(truth, 0.2f, 0.1f, Config::kMaxParticles);
  g_lp = &g_loop.emplace(estimator, Rig::kTiming);

  const float m_per_tick = est::kTwoPi * config.motion.wheel_radius / static_cast<float>(config.motion.ticks_per_rev);
  TimeNs t = 0;
  std::int32_t k = 0;
  // Encoder ticks of 10 ms of the route (straight for 1 s, then an arc) at the next 10 ms, the truth moved with them.
  const auto ticks_of = [&](TimeNs dt_ns) {
    ++k;
    t += dt_ns;
    const float dt = static_cast<float>(dt_ns) * 1e-9f;
    const float v = 0.5f, w = k > 100 ? 0.4f : 0.0f, b = config.motion.track_width;
    const std::int32_t tl = static_cast<std::int32_t>((v - 0.5f * w * b) * dt / m_per_tick + 0.5f);
    const std::int32_t tr = static_cast<std::int32_t>((v + 0.5f * w * b) * dt / m_per_tick + 0.5f);
    truth = est::DiffDriveMotionModel::predict(truth, {tl, tr}, config.motion);
    return est::loop::WheelTicksInput{t, {tl, tr}, 2};
  };
  const auto scan_at = [&](float* ranges, bool max_range) {
    if (max_range)
      for (std::int32_t j = 0; j < kBeams; ++j) ranges[j] = kRangeMax;
    else
      scan_from(caster, truth, ranges);
    return est::loop::ScanInput{t, kLayout, ranges};
  };

  board::StepCounts correct, predict, max_range;
  std::uint64_t worst = 0;
  bool pushed = true;
  board::stack_paint();
  // Typical: 3 s, a scan every 10th encoder sample.
  for (int i = 1; i <= 300; ++i) {
    pushed = g_lp->push(ticks_of(10 * kMs)) && pushed;
    if (i % 10 == 0) pushed = g_lp->push(scan_at(g_ranges[0], false)) && pushed;
    const std::uint32_t corrections = g_lp->counters().corrections;
    const std::uint64_t n = board::counted_step();
    (g_lp->counters().corrections != corrections ? correct : predict).add(n);
  }
  // A scan with every beam at max range (once the last scan of the route was applied), then the steps until it is.
  for (int i = 0; i < 3; ++i) {
    pushed = g_lp->push(ticks_of(10 * kMs)) && pushed;
    board::counted_step();
  }
  pushed = g_lp->push(ticks_of(10 * kMs)) && pushed;
  pushed = g_lp->push(scan_at(g_ranges[1], true)) && pushed;
  for (int i = 0; i < 4; ++i) {
    const std::uint32_t corrections = g_lp->counters().corrections;
    const std::uint64_t n = board::counted_step();
    if (g_lp->counters().corrections != corrections) max_range.add(n);
    pushed = g_lp->push(ticks_of(10 * kMs)) && pushed;
  }
  board::counted_step();
  // The worst step: a full queue after a gap of 1 s.
  const std::uint32_t predictions = g_lp->counters().predictions;
  pushed = g_lp->push(ticks_of(1000 * kMs)) && pushed;
  for (int i = 0; g_lp->pending() + 1u < Config::kQueueCapacity; ++i) {  // bounded by the queue's capacity
    pushed = g_lp->push(ticks_of(10 * kMs)) && pushed;
    if (i == 10) pushed = g_lp->push(scan_at(g_ranges[0], false)) && pushed;
    if (i == 20) pushed = g_lp->push(scan_at(g_ranges[1], true)) && pushed;
  }
  pushed = g_lp->push(ticks_of(30 * kMs)) && pushed;
  const std::uint32_t queued = g_lp->pending();
  worst = board::counted_step();
  const std::uint32_t worst_predictions = g_lp->counters().predictions - predictions;
  for (int i = 0; i < 40; ++i) {
    pushed = g_lp->push(ticks_of(10 * kMs)) && pushed;
    if (i % 10 == 5) pushed = g_lp->push(scan_at(g_ranges[2], false)) && pushed;
    board::counted_step();
  }
  const std::uint32_t stack = board::stack_high_water();
  g_lp->flush(g_clock, g_sink);

  const est::loop::LoopCounters& lc = g_lp->counters();
  board::write("reference-mcl: loop: inputs ");
  board::write_dec(lc.inputs);
  board::write(", predictions ");
  board::write_dec(lc.predictions);
  board::write(", corrections ");
  board::write_dec(lc.corrections);
  board::write(", rejected ");
  board::write_dec(lc.rejected);
  board::write(", degenerate ");
  board::write_dec(lc.degenerate);
  board::write(", too old ");
  board::write_dec(lc.too_old);
  board::write(", queue full ");
  board::write_dec(lc.queue_full);
  board::write("\n");
  board::write_counts("reference-mcl", "typical steps with a scan correction", correct);
  board::write_counts("reference-mcl", "typical steps that only predict", predict);
  board::write_counts("reference-mcl", "the step of a scan with every beam at max range", max_range);
  board::write("reference-mcl: the worst step (a full queue of ");
  board::write_dec(queued);
  board::write(" inputs after a gap of 1 s, every input but the last applied: ");
  board::write_dec(worst_predictions);
  board::write(" predictions, 2 corrections): ");
  board::write_dec(worst);
  board::write(" instructions\nreference-mcl: stack of a step (painted): ");
  board::write_dec(stack);
  board::write(" bytes\n");
  board::report_budget("mcl.step.correct", correct.mean(), "instructions");
  board::report_budget("mcl.step.predict", predict.mean(), "instructions");
  board::report_budget("mcl.step.max_range_scan", max_range.mean(), "instructions");
  board::report_budget("mcl.step.worst", worst, "instructions");
  board::report_budget("mcl.stack.step", stack, "bytes");

  const est::Pose2 e = g_sink.last.estimate.mean;
  const float dx = e.x - truth.x, dy = e.y - truth.y;
  const bool tracked = g_sink.outputs > 0u && dx * dx + dy * dy < 0.25f;
  const bool ok = pushed && tracked && queued == Config::kQueueCapacity && correct.steps >= 25u &&
                  max_range.steps == 1u && worst_predictions >= 100u && stack < board::kStackPaintWindow;
  board::write(ok ? "reference-mcl: PASS\n" : "reference-mcl: FAIL (the workload went wrong)\n");
  return ok ? 0 : 1;
}
