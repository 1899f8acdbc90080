// bench-mcl for the qemu mps2 boards: instructions per Monte Carlo localization step for N = 512 particles and
// K = 60 beams (Thrun table 8.3 with a bicycle model, likelihood-field or beam-model correction, low-variance
// resampling), counted with SysTick under `qemu -icount shift=10` (instruction_counter.hpp; the ctest runs it so).
//
// The map is an 8 m x 6 m room at 0.05 m (160 x 120 cells: grid 19 KiB, distance transform 38 KiB, per-cell
// likelihood field 75 KiB), the particles a tracking cloud (0.3 m, 0.1 rad) around the true pose, the scan 60 beams
// over 360 deg cast from the true pose. Each phase is counted separately over several steps and averaged.
#include <cstdint>

#include "est/filter/augmented_mcl.hpp"
#include "est/filter/free_space_sampler.hpp"
#include "est/map/cone_ray_caster.hpp"
#include "est/map/distance_transform.hpp"
#include "est/map/ray_casting.hpp"
#include "est/motion/bicycle_model.hpp"
#include "est/motion/motion_batch.hpp"
#include "est/sensor/beam_range_finder_model.hpp"
#include "est/sensor/beam_range_finder_model_cone.hpp"
#include "est/sensor/likelihood_field_grid.hpp"
#include "est/sensor/likelihood_field_range_finder_model.hpp"
#include "est/sensor/range_scan.hpp"
#include "bench_beam_density.hpp"
#include "budget_report.hpp"
#include "instruction_counter.hpp"
#include "semihosting.hpp"

namespace {

constexpr std::uint32_t kN = 512;
constexpr std::int32_t kK = 60;
constexpr int kSteps = 4;

est::OccupancyGridStorage<160, 120> g_grid;
est::DistanceTransformStorage<160, 120> g_edt;
est::LikelihoodFieldGridStorage<160, 120> g_field_grid;
est::LikelihoodField g_field;
est::PreparedScan<kK> g_scan;
est::AugmentedMcl<kN> g_mcl(est::MclConfig{}, 0u);
// The beam model's exact cone caster: 16 headings, one byte per cell and heading (307 KB here, 77 KB build scratch).
constexpr std::int32_t kConeBins = 16;
#if EST_BENCH_CONE_PACKED
// bench-mcl-packed: the same table packed in 4 bits per cell and heading (154 KB here; kConeLevels), what fits
// 512 KiB on a 200 x 200 map at 16 headings (312 KiB) where bytes would need 8 headings. An image of its own, as a
// firmware would hold one kind: two kinds in one image change GCC's inlining of both (measured).
est::ConeRayCasterStorage<kConeBins, 160, 120, 4> g_cone;
constexpr const char* kConePhase = "correct_beam_cone_packed";
#else
est::ConeRayCasterStorage<kConeBins, 160, 120> g_cone;
constexpr const char* kConePhase = "correct_beam_cone";
#endif
est::BeamBearingsStorage<kK> g_bearings;
est::BeamReadingsStorage<kK> g_readings;
volatile float g_cone_sink = 0.0f;
#if !EST_BENCH_CONE_PACKED
float g_z_exp[kN * kK];  // each particle-beam's z*, for the density phase
#endif

void build_room() {
  g_grid.configure(160, 120, 0.05f, 0.0f, 0.0f, est::kFreeCell);
  g_grid.fill_rect(0, 0, 159, 1, est::kOccupiedCell);
  g_grid.fill_rect(0, 118, 159, 119, est::kOccupiedCell);
  g_grid.fill_rect(0, 0, 1, 119, est::kOccupiedCell);
  g_grid.fill_rect(158, 0, 159, 119, est::kOccupiedCell);
  g_grid.fill_rect(100, 0, 101, 70, est::kOccupiedCell);   // a partition with a gap
  g_grid.fill_rect(20, 20, 50, 34, est::kOccupiedCell);    // a table
  g_grid.fill_rect(120, 90, 126, 96, est::kOccupiedCell);  // a post
}

struct Phase {
  const char* name;
  std::uint64_t instructions = 0;
};

void print_phase(const Phase& p, std::uint64_t per) {
  board::write(" ");
  board::write(p.name);
  board::write(" ");
  board::write_dec(p.instructions / kSteps);
  if (per > 0u) {
    board::write(" (");
    board::write_dec(p.instructions / kSteps / per);
    board::write(per == kN ? "/particle)" : "/particle-beam)");
  }
}

}  // namespace

int main() {
  build_room();
  g_edt.build(g_grid.grid());
  const est::OccupancyGrid grid = g_grid.grid();
  est::LikelihoodFieldParams lp;
  lp.range_max = 8.0f;
  g_field.configure(lp, grid, g_edt.view());
  g_field_grid.build(g_field, grid);
  est::BeamRangeFinderModel beam;
  est::BeamModelParams bp;
  bp.range_max = 8.0f;
  beam.configure(bp);
  const est::DistanceTransformRayCaster caster(grid, g_edt.view());
  const bool cone_ok = g_cone.build(grid, kConeBins) == est::ConeRayCasterStatus::ok;
  const auto cone = g_cone.view();
  const est::FreeSpaceSampler free_space(grid, g_edt.view(), 0.2f);
  const est::LikelihoodFieldGrid field = g_field_grid.view();

  est::BicycleParams noise;
  noise.frame_length = 0.6f;
  noise.steer_sigma = 0.04f;
  noise.speed_var_per_speed = 0.008f;
  noise.final_rot_sigma = 0.01f;
  const est::BicycleControl u{0.8f, 0.1f};
  const est::ScanLayout layout{-est::kPi, est::kTwoPi / kK, kK, 0.05f, 8.0f};
  const est::Pose2 mount{};
  est::Pose2 truth{3.0f, 4.0f, 0.2f};
  est::Rng world(5u);
  est::MclConfig cfg;
  cfg.recovery = false;              // steady-state tracking: no injection
  cfg.resample_ess_fraction = 1.1f;  // resample every step, so every step pays for it
  g_mcl = est::AugmentedMcl<kN>(cfg, 2026u);
  g_mcl.initialize_gaussian(truth, 0.3f, 0.1f, kN);

  Phase predict{"predict"}, predict_batch{"predict_batch"}, lf{"correct_lf"}, lf_scalar{"correct_lf_scalar"},
      bm{"correct_beam"}, bm_cone{kConePhase}, resample{"resample"};
#if !EST_BENCH_CONE_PACKED
  Phase density{"beam_density"};
#endif
  for (int t = 0; t < kSteps; ++t) {
    truth = est::BicycleMotionModel::sample(truth, u, noise, world);
    float ranges[kK];
    for (std::int32_t k = 0; k < kK; ++k) {
      float s = 0.0f, c = 0.0f;
      est::fmath::sincos(truth.theta + layout.angle_min + static_cast<float>(k) * layout.angle_increment, s, c);
      ranges[k] = caster.cast(truth.x, truth.y, c, s, 8.0f) + world.uniform(-0.02f, 0.02f);
    }
    g_scan.prepare(layout, ranges);
    const est::ScanBeams z = g_scan.beams();

    // Both predictions are counted; the filter moves by the per-particle one on even steps, the batched on odd.
    if (t % 2 == 0) {
      board::instruction_counter_start();
      g_mcl.predict<est::BicycleMotionModel>(u, noise);
      predict.instructions += 2u * board::instruction_counter_read();
    } else {
      board::instruction_counter_start();
      g_mcl.predict_batch<est::BicycleMotionModel>(u, noise);
      predict_batch.instructions += 2u * board::instruction_counter_read();
    }

    // The three corrections are counted on the same prior weights; the likelihood-field one is kept.
    board::instruction_counter_start();
    g_mcl.correct([&](const est::Pose2& x) { return est::beam_range_finder_model(z, x, mount, caster, beam); });
    bm.instructions += board::instruction_counter_read();
    // The same beam model with the exact cone caster (the same z*), bearings and readings prepared per scan.
    board::instruction_counter_start();
    g_bearings.prepare(z, kConeBins);
    g_readings.prepare(z, beam);
    {
      // Weights only (the filter is left as it is; the normalization the other corrections count is ~1 %).
      const est::ConstParticleSetView p = g_mcl.particles();
      for (std::uint32_t i = 0; i < p.count; ++i)
        g_cone_sink = g_cone_sink + est::beam_range_finder_model(z, g_bearings.view(), g_readings.view(),
                                                                 p.pose(i), mount, cone, beam);
    }
    bm_cone.instructions += board::instruction_counter_read();
#if !EST_BENCH_CONE_PACKED
    // The same beam model's density and product alone, at the z* the cone caster gives (cast before counting).
    density.instructions += board::count_beam_density(z, g_readings.view(), g_mcl.particles(), mount, cone, beam,
                                                      g_z_exp, g_cone_sink);
#endif
    board::instruction_counter_start();
    g_mcl.correct([&](const est::Pose2& x) { return est::likelihood_field_range_finder_model(z, x, mount, g_field); });
    lf_scalar.instructions += board::instruction_counter_read();
    board::instruction_counter_start();
    g_mcl.correct_batch([&](est::ConstParticleSetView p, float* out) {
      est::likelihood_field_range_finder_model_batch(z, p.x, p.y, p.theta, p.count, mount, field, out);
    });
    lf.instructions += board::instruction_counter_read();

    board::instruction_counter_start();
    g_mcl.resample(free_space);
    resample.instructions += board::instruction_counter_read();
  }
  const std::uint64_t pb = static_cast<std::uint64_t>(kN) * kK;
  board::write("bench-mcl " EST_BOARD_NAME " N=512 K=60 steps=4 instructions per step:");
  print_phase(predict, kN);
  print_phase(predict_batch, kN);
  print_phase(lf, pb);
  print_phase(lf_scalar, pb);
  print_phase(bm, pb);
  print_phase(bm_cone, pb);
#if !EST_BENCH_CONE_PACKED
  print_phase(density, pb);
#endif
  print_phase(resample, kN);
  board::write("\nbench-mcl " EST_BOARD_NAME " MCL step (predict + likelihood field + resample): ");
  board::write_dec((predict.instructions + lf.instructions + resample.instructions) / kSteps);
  board::write(" instructions; with batched prediction: ");
  board::write_dec((predict_batch.instructions + lf.instructions + resample.instructions) / kSteps);
  board::write("; with the beam model instead: ");
  board::write_dec((predict.instructions + bm.instructions + resample.instructions) / kSteps);
  board::write("\n");
  // Per step of N = 512, K = 60 (the per-particle and per-beam figures round too coarsely to be budgets).
#if EST_BENCH_CONE_PACKED
  board::report_budget("bench.mcl_packed.beam_model_cone", bm_cone.instructions / kSteps, "instructions");
#else
  board::report_budget("bench.mcl.predict_batch", predict_batch.instructions / kSteps, "instructions");
  board::report_budget("bench.mcl.likelihood_field", lf.instructions / kSteps, "instructions");
  board::report_budget("bench.mcl.beam_model", bm.instructions / kSteps, "instructions");
  board::report_budget("bench.mcl.beam_model_cone", bm_cone.instructions / kSteps, "instructions");
  board::report_budget("bench.mcl.beam_density", density.instructions / kSteps, "instructions");
  board::report_budget("bench.mcl.resample", resample.instructions / kSteps, "instructions");
  board::report_budget("bench.mcl.step",
                       (predict_batch.instructions + lf.instructions + resample.instructions) / kSteps, "instructions");
#endif
  // Calibration of the counter: a loop of exactly 2 x 1000000 instructions (subs + bne), which spans three SysTick
  // wraps; the figure printed should be 2000000 plus the counter's own few instructions.
  board::instruction_counter_start();
  std::uint32_t left = 1000000u;
  __asm__ volatile("1: subs %0, %0, #1\n bne 1b" : "+r"(left) : : "cc");
  const std::uint64_t counted = board::instruction_counter_read();
  board::write("bench-mcl counter calibration: a 2000000-instruction loop counts ");
  board::write_dec(counted);
  const bool calibrated = counted >= 2000000u && counted <= 2000100u;  // fails without -icount shift=10, too
  board::write(calibrated ? "\n" : " FAIL (run under qemu -icount shift=10)\n");
  const est::PoseEstimate e = g_mcl.estimate();
  const float dx = e.mean.x - truth.x, dy = e.mean.y - truth.y;
  const bool tracking = dx * dx + dy * dy < 0.25f;  // a sanity check that the counted work is real filtering
  board::write(tracking ? "bench-mcl estimate within 0.5 m of the truth\n" : "bench-mcl FAIL estimate lost\n");
  if (!cone_ok) board::write("bench-mcl FAIL cone caster build\n");
  return tracking && calibrated && cone_ok ? 0 : 1;
}
