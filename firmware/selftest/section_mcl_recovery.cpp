#include "est/filter/augmented_mcl.hpp"
#include "est/filter/free_space_sampler.hpp"
#include "est/map/ray_casting.hpp"
#include "est/motion/bicycle_model.hpp"
#include "est/loop/likelihood_field_scan.hpp"
#include "est/motion/motion_batch.hpp"
#include "est/sensor/likelihood_field_range_finder_model.hpp"
#include "est/sensor/range_scan.hpp"
#include "est/util/trace.hpp"
#include "mcl_room.hpp"
#include "selftest.hpp"

namespace est::selftest {
namespace {

PreparedScan<60> g_scan;
AugmentedMcl<2048> g_mcl(MclConfig{}, 0u);

// 6.4 m x 4.8 m at 0.1 m: walls, a partition with a door, a desk and a post, so that a kidnapping across the room
// is visible in the scan.
void furnish(MclRoomGrid& g) {
  g.fill_rect(32, 0, 33, 18, kOccupiedCell);   // partition, a door between y = 1.9 m and 2.9 m
  g.fill_rect(32, 29, 33, 47, kOccupiedCell);
  g.fill_rect(8, 30, 18, 34, kOccupiedCell);   // desk
  g.fill_rect(48, 10, 50, 12, kOccupiedCell);  // post
}

}  // namespace

// Augmented MCL's recovery with the per-beam statistic (est/filter/augmented_mcl.hpp): N <= 2048 with KLD (table
// 8.4, bins of the samples drawn, random ones included), K = 60 likelihood-field beams with their MeasurementScale,
// a bicycle tracked from a Gaussian for 1 s, then kidnapped across the partition for 3 s: the lost scans inject at
// once, a false find holds the injection until it plateaus, the next injection finds the robot and the roughened
// cloud converges to tracking again. Digest of the statistic, the averages, the injection probability, the
// estimate and the count after every step, the counters and the final set.
void section_mcl_recovery(Trace& d) {
  d.scope("mcl_recovery");
  const MclRoom room = mcl_room(furnish);
  // The loop's range model: the batched likelihood field on the per-cell grid, with its MeasurementScale.
  const loop::LikelihoodFieldScan range_model(room.field, Pose2{}, &room.field_grid);
  const FreeSpaceSampler& free_space = room.free_space;
  const auto is_free = [&room](float x, float y) { return room.is_free(x, y); };

  const BicycleParams noise = mcl_room_bicycle();
  const BicycleControl u{0.4f, 0.1f};
  const ScanLayout layout = mcl_room_scan_layout();

  MclConfig cfg;
  cfg.alpha_slow = 0.02f;
  cfg.alpha_fast = 0.3f;
  cfg.kld = true;
  cfg.kld_config.n_min = 64;
  g_mcl = AugmentedMcl<2048>(cfg, 20270105u);
  Pose2 truth{1.2f, 1.2f, 0.2f};
  g_mcl.initialize_gaussian(truth, 0.1f, 0.05f, 256);
  Rng world(91u);
  for (int t = 0; t < 40; ++t) {
    d.step(static_cast<std::uint32_t>(t));
    if (t == 10) truth = {4.6f, 3.4f, -2.0f};  // kidnapped: through the partition, 3.8 m away
    truth = BicycleMotionModel::sample(truth, u, noise, world);
    g_mcl.predict_in_map_batch<BicycleMotionModel>(u, noise, is_free);
    float ranges[kMclRoomBeams];
    mcl_room_scan(room, truth, world, ranges);
    g_scan.prepare(layout, ranges);
    const ScanBeams z = g_scan.beams();
    const CorrectionReport r = range_model.correct(g_mcl, z, loop::ScanContext{});
    d.add("fit", r.fit);
    d.add("ess", r.ess);
    d.add("log_w_slow", g_mcl.log_w_slow());
    d.add("log_w_fast", g_mcl.log_w_fast());
    d.add("injection_probability", g_mcl.injection_probability());
    d.add_u32("found", g_mcl.last_found() ? 1u : 0u);
    const PoseEstimate e = g_mcl.cluster_estimate(0.5f).strongest;
    d.add("x", e.mean.x);
    d.add("y", e.mean.y);
    d.add("theta", e.mean.theta);
    g_mcl.resample(free_space);
    d.add_u32("particles", g_mcl.particles().count);
  }
  d.step(40);
  add_particles(d, g_mcl.particles());
  d.add_u32("drawn_particles", g_mcl.counters().drawn_particles);
  d.add_u32("injected_particles", g_mcl.counters().injected_particles);
  d.add_u32("resamplings", g_mcl.counters().resamplings);
  d.add("truth_x", truth.x);
  d.add("truth_y", truth.y);
}

}  // namespace est::selftest
