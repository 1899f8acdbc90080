#include "est/filter/augmented_mcl.hpp"
#include "est/filter/free_space_sampler.hpp"
#include "est/map/ray_casting.hpp"
#include "est/motion/bicycle_model.hpp"
#include "est/motion/motion_batch.hpp"
#include "est/sensor/beam_range_finder_model.hpp"
#include "est/sensor/likelihood_field_range_finder_model.hpp"
#include "est/sensor/range_scan.hpp"
#include "est/util/trace.hpp"
#include "mcl_room.hpp"
#include "selftest.hpp"

namespace est::selftest {
namespace {

PreparedScan<60> g_scan;
AugmentedMcl<256> g_mcl(MclConfig{}, 0u);

// 6.4 m x 4.8 m at 0.1 m, an L-shaped room with a desk and a post: asymmetric, so a uniform start converges.
void furnish(MclRoomGrid& g) {
  g.fill_rect(44, 30, 63, 47, kOccupiedCell);  // the L's missing corner
  g.fill_rect(10, 8, 22, 12, kOccupiedCell);   // desk
  g.fill_rect(35, 18, 37, 20, kOccupiedCell);  // post
}

}  // namespace

// Monte Carlo localization (Thrun table 8.3): N = 256, K = 60 beams, a bicycle driving an arc; global start, map-
// conditioned prediction (per particle, and batched every third step), likelihood-field (batched) and beam-model
// corrections on alternate steps, low-variance resampling with uniform injection. Digest of the particles and the
// estimate after every step.
void section_mcl(Trace& d) {
  d.scope("mcl");
  const MclRoom room = mcl_room(furnish);
  BeamRangeFinderModel beam;
  BeamModelParams bp;
  bp.range_max = 6.0f;
  beam.configure(bp);
  const DistanceTransformRayCaster& caster = room.caster;
  const FreeSpaceSampler& free_space = room.free_space;
  const auto is_free = [&room](float x, float y) { return room.is_free(x, y); };

  const BicycleParams noise = mcl_room_bicycle();
  const BicycleControl u{0.5f, 0.15f};
  const ScanLayout layout = mcl_room_scan_layout();
  const Pose2 mount{};

  g_mcl = AugmentedMcl<256>(MclConfig{}, 20261124u);
  g_mcl.initialize_global(free_space, 256);
  Pose2 truth{1.5f, 2.5f, 0.3f};
  Rng world(77u);
  for (int t = 0; t < 12; ++t) {
    d.step(static_cast<std::uint32_t>(t));
    truth = BicycleMotionModel::sample(truth, u, noise, world);
    if (t % 3 == 2)  // the batched prediction (bulk normals, inline trigonometry, vectorized on the host) too
      g_mcl.predict_in_map_batch<BicycleMotionModel>(u, noise, is_free);
    else
      g_mcl.predict_in_map<BicycleMotionModel>(u, noise, is_free);
    float ranges[kMclRoomBeams];
    mcl_room_scan(room, truth, world, ranges);
    g_scan.prepare(layout, ranges);
    const ScanBeams z = g_scan.beams();
    CorrectionReport r{};
    if (t % 2 == 0) {
      const LikelihoodFieldGrid field = room.field_grid;
      r = g_mcl.correct_batch([&](ConstParticleSetView p, float* out) {
        likelihood_field_range_finder_model_batch(z, p.x, p.y, p.theta, p.count, mount, field, out);
      });
    } else {
      r = g_mcl.correct([&](const Pose2& x) { return beam_range_finder_model(z, x, mount, caster, beam); });
    }
    d.add("log_mean_likelihood", r.log_mean_likelihood);
    d.add("ess", r.ess);
    g_mcl.resample(free_space);
    const PoseEstimate e = g_mcl.cluster_estimate(0.5f).strongest;
    d.add("x", e.mean.x);
    d.add("y", e.mean.y);
    d.add("theta", e.mean.theta);
    d.add_matrix("P", e.covariance);
  }
  d.step(12);
  add_particles(d, g_mcl.particles());
  d.add_u32("injected_particles", g_mcl.counters().injected_particles);
  d.add_u32("map_penalized", g_mcl.counters().map_penalized);
  d.add_u32("resamplings", g_mcl.counters().resamplings);
}

}  // namespace est::selftest
