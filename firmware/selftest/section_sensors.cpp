#include "est/map/distance_transform.hpp"
#include "est/map/landmark_map.hpp"
#include "est/map/occupancy_grid.hpp"
#include "est/map/ray_casting.hpp"
#include "est/random/xoshiro128.hpp"
#include "est/sensor/beam_range_finder_model.hpp"
#include "est/sensor/landmark_model.hpp"
#include "est/sensor/likelihood_field_range_finder_model.hpp"
#include "est/sensor/range_only_model.hpp"
#include "est/sensor/range_scan.hpp"
#include "est/sensor/steered_range_finder.hpp"
#include "est/util/digest.hpp"
#include "selftest.hpp"

namespace est::selftest {
namespace {

// 6.4 m x 4.8 m at 0.1 m: a room with a partition, a desk and a pillar (~3 KiB grid, 6 KiB transform).
OccupancyGridStorage<64, 48> g_grid;
DistanceTransformStorage<64, 48> g_edt;
PreparedScan<72> g_scan;
LikelihoodField g_field;
LandmarkMapStorage<4> g_landmarks;

void build_room() {
  g_grid.configure(64, 48, 0.1f, -0.5f, -0.3f, kFreeCell);
  g_grid.fill_rect(0, 0, 63, 0, kOccupiedCell);
  g_grid.fill_rect(0, 47, 63, 47, kOccupiedCell);
  g_grid.fill_rect(0, 0, 0, 47, kOccupiedCell);
  g_grid.fill_rect(63, 0, 63, 47, kOccupiedCell);
  g_grid.fill_rect(40, 0, 40, 30, kOccupiedCell);
  g_grid.fill_rect(10, 10, 18, 13, kOccupiedCell);
  g_grid.fill_rect(50, 36, 52, 38, kOccupiedCell);
  g_grid.fill_rect(20, 35, 30, 40, kUnknownCell);
}

}  // namespace

// Maps and sensor models (Thrun ch. 6): distance transform, both ray casters, beam, likelihood-field, steered,
// landmark and range-only models on a small synthetic room.
std::uint64_t section_sensors() {
  Digest d;
  build_room();
  g_edt.build(g_grid.grid());
  const OccupancyGrid grid = g_grid.grid();
  const DistanceTransform edt = g_edt.view();
  for (std::int32_t i = 0; i < grid.cell_count(); i += 7) d.add_u32(edt.data()[i]);

  const GridRayCaster exact(grid);
  const DistanceTransformRayCaster fast(grid, edt);
  Rng rng(20261123u);
  for (int i = 0; i < 256; ++i) {
    const float x = rng.uniform(-0.4f, 5.8f), y = rng.uniform(-0.2f, 4.4f), th = rng.uniform(-kPi, kPi);
    float s = 0.0f, c = 0.0f;
    fmath::sincos(th, s, c);
    d.add(exact.cast(x, y, c, s, 8.0f));
    d.add(fast.cast(x, y, c, s, 8.0f));
  }

  // A 72 x 5 deg scan simulated from a true pose, with two bad readings.
  const Pose2 truth{1.7f, 2.9f, 0.4f};
  const Pose2 mount{0.1f, 0.0f, 0.0f};
  const ScanLayout layout{-kPi, kTwoPi / 72.0f, 72, 0.02f, 6.0f};
  float ranges[72];
  const SensorFrame f = sensor_frame(truth, mount);
  for (int k = 0; k < 72; ++k) {
    float s = 0.0f, c = 0.0f;
    fmath::sincos(layout.angle_min + static_cast<float>(k) * layout.angle_increment, s, c);
    ranges[k] = fast.cast(f.x, f.y, f.c * c - f.s * s, f.s * c + f.c * s, 6.0f) + rng.uniform(-0.02f, 0.02f);
  }
  ranges[5] = -1.0f;
  ranges[6] = __builtin_nanf("");
  g_scan.prepare(layout, ranges, 1);
  const ScanBeams b = g_scan.beams();
  d.add_u32(static_cast<std::uint32_t>(b.count));

  BeamRangeFinderModel beam;
  BeamModelParams bp;
  bp.range_max = 6.0f;
  beam.configure(bp);
  LikelihoodFieldParams lp;
  lp.range_max = 6.0f;
  g_field.configure(lp, grid, edt);
  for (int i = 0; i < 16; ++i) {
    const Pose2 x{truth.x + rng.uniform(-0.3f, 0.3f), truth.y + rng.uniform(-0.3f, 0.3f),
                  truth.theta + rng.uniform(-0.2f, 0.2f)};
    d.add(beam_range_finder_model(b, x, mount, exact, beam));
    d.add(beam_range_finder_model(b, x, mount, fast, beam));
    d.add(likelihood_field_range_finder_model(b, x, mount, g_field));
  }
  for (float z = 0.0f; z <= 6.5f; z += 0.25f) d.add(beam.log_density(z, 3.0f));

  SteeredMount handlebar;
  handlebar.pivot_x = 0.05f;
  handlebar.sensor_on_part = {0.05f, 0.0f, 0.0f};
  const float alphas[3] = {-0.2f, 0.0f, 0.2f};
  const float probs[3] = {0.25f, 0.5f, 0.25f};
  d.add(steered_beam_range_finder_model(b, truth, handlebar, alphas, probs, 3, fast, beam));
  d.add(steered_likelihood_field_range_finder_model(b, truth, handlebar, alphas, probs, 3, g_field));

  g_landmarks.clear();
  g_landmarks.add({0.5f, 4.0f, 1.0f});
  g_landmarks.add({5.5f, 0.5f, 2.0f});
  g_landmarks.add({3.0f, 2.0f, 3.0f});
  const LandmarkMap lm = g_landmarks.view();
  const LandmarkNoise noise{0.05f, 0.02f, 0.1f};
  for (std::int32_t j = 0; j < lm.size(); ++j) {
    const LandmarkMeasurement z = sample_landmark_measurement(truth, lm[j], noise, rng);
    d.add(z.range);
    d.add(z.bearing);
    d.add(landmark_model_known_correspondence(z, j, truth, lm, noise));
    d.add(range_only_model(z.range, truth, lm[j].x, lm[j].y, noise.sigma_range));
  }
  const TwoLandmarkPose p = pose_from_two_landmarks(lm[0], expected_landmark_measurement(truth, lm[0]), lm[1],
                                                    expected_landmark_measurement(truth, lm[1]));
  d.add_u32(static_cast<std::uint32_t>(p.status));
  d.add(p.pose.x);
  d.add(p.pose.y);
  d.add(p.pose.theta);
  return d.value();
}

}  // namespace est::selftest
