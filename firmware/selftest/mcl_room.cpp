#include "mcl_room.hpp"

#include "est/map/distance_transform.hpp"
#include "est/math/fmath.hpp"

namespace est::selftest {
namespace {

MclRoomGrid g_grid;
DistanceTransformStorage<64, 48> g_edt;
LikelihoodFieldGridStorage<64, 48> g_field_grid;
LikelihoodField g_field;

}  // namespace

MclRoom mcl_room(void (*furnish)(MclRoomGrid&)) {
  g_grid.configure(64, 48, 0.1f, 0.0f, 0.0f, kFreeCell);
  g_grid.fill_rect(0, 0, 63, 0, kOccupiedCell);
  g_grid.fill_rect(0, 47, 63, 47, kOccupiedCell);
  g_grid.fill_rect(0, 0, 0, 47, kOccupiedCell);
  g_grid.fill_rect(63, 0, 63, 47, kOccupiedCell);
  furnish(g_grid);
  g_edt.build(g_grid.grid());
  const OccupancyGrid grid = g_grid.grid();
  LikelihoodFieldParams lp;
  lp.z_hit = 0.85f;
  lp.z_rand = 0.10f;
  lp.range_max = 6.0f;
  g_field.configure(lp, grid, g_edt.view());
  g_field_grid.build(g_field, grid);
  return MclRoom{grid, g_field, g_field_grid.view(), DistanceTransformRayCaster(grid, g_edt.view()),
                 FreeSpaceSampler(grid, g_edt.view(), 0.2f)};
}

ScanLayout mcl_room_scan_layout() { return ScanLayout{-kPi, kTwoPi / 60.0f, kMclRoomBeams, 0.05f, 6.0f}; }

void mcl_room_scan(const MclRoom& room, const Pose2& truth, Rng& world, float (&ranges)[kMclRoomBeams]) {
  const ScanLayout layout = mcl_room_scan_layout();
  for (std::int32_t k = 0; k < kMclRoomBeams; ++k) {
    float s = 0.0f, c = 0.0f;
    fmath::sincos(truth.theta + layout.angle_min + static_cast<float>(k) * layout.angle_increment, s, c);
    ranges[k] = room.caster.cast(truth.x, truth.y, c, s, 6.0f) + world.uniform(-0.02f, 0.02f);
  }
}

BicycleParams mcl_room_bicycle() {
  BicycleParams b;
  b.frame_length = 0.5f;
  b.steer_sigma = 0.03f;
  b.speed_var_per_speed = 0.005f;
  b.final_rot_sigma = 0.01f;
  return b;
}

void add_particles(Trace& d, ConstParticleSetView p) {
  for (std::uint32_t i = 0; i < p.count; ++i) {
    d.add("particle_x", p.x[i]);
    d.add("particle_y", p.y[i]);
    d.add("particle_theta", p.theta[i]);
    d.add("particle_log_w", p.log_w[i]);
  }
}

}  // namespace est::selftest
