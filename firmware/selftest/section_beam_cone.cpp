#include "est/map/cone_ray_caster.hpp"
#include "est/map/occupancy_grid.hpp"
#include "est/map/ray_casting.hpp"
#include "est/random/xoshiro128.hpp"
#include "est/sensor/beam_range_finder_model_cone.hpp"
#include "est/sensor/beam_readings.hpp"
#include "est/sensor/range_scan.hpp"
#include "est/util/digest.hpp"
#include "beam_room.hpp"
#include "selftest.hpp"

namespace est::selftest {
namespace {

// The beam sections' room (beam_room.hpp) with a pillar; 16 headings, in bytes and packed (48 + 24 KiB).
OccupancyGridStorage<64, 48> g_room;
ConeRayCasterStorage<16, 64, 48> g_cone;
ConeRayCasterStorage<16, 64, 48, 4> g_packed;
PreparedScan<71> g_scan;
BeamBearingsStorage<71> g_bearings;
BeamReadingsStorage<71> g_readings;

}  // namespace

// The beam model over the exact cone caster, bytes and packed: single casts, and the model at 32 poses. 71 beams,
// so the host's lanes walk a chunk of 64 and a last group of 16 padded with refused rays, and the boards their
// scalar loop: the digests must agree.
std::uint64_t section_beam_cone() {
  Digest d;
  Rng rng(20261207u);
  furnish_beam_room(g_room);
  g_room.fill_rect(50, 38, 51, 39, kOccupiedCell);
  const OccupancyGrid grid = g_room.grid();
  d.add_u32(static_cast<std::uint32_t>(g_cone.build(grid, 16)));
  d.add_u32(static_cast<std::uint32_t>(g_packed.build(grid, 16)));
  const ConeRayCaster cone = g_cone.view();
  const PackedConeRayCaster packed = g_packed.view();
  for (int i = 0; i < 256; ++i) {
    const float x = rng.uniform(-0.6f, 5.9f), y = rng.uniform(-0.4f, 4.5f), th = rng.uniform(-kPi, kPi);
    float s = 0.0f, c = 0.0f;
    fmath::sincos(th, s, c);
    d.add(cone.cast(x, y, c, s, 6.0f));
    d.add(packed.cast(x, y, c, s, 6.0f));
  }

  const Pose2 truth{1.7f, 2.9f, 0.4f};
  beam_room_scan(grid, truth, rng, g_scan);
  const ScanBeams b = g_scan.beams();
  const BeamRangeFinderModel beam = beam_room_model();
  d.add_u32(g_bearings.prepare(b, cone.bins()) ? 1u : 0u);
  d.add_u32(g_readings.prepare(b, beam) ? 1u : 0u);
  for (int i = 0; i < 32; ++i) {
    const Pose2 x{truth.x + rng.uniform(-0.6f, 0.6f), truth.y + rng.uniform(-0.6f, 0.6f),
                  truth.theta + rng.uniform(-0.5f, 0.5f)};
    d.add(beam_range_finder_model(b, g_bearings.view(), g_readings.view(), x, {}, cone, beam));
    d.add(beam_range_finder_model(b, g_bearings.view(), g_readings.view(), x, {}, packed, beam));
  }
  return d.value();
}

}  // namespace est::selftest
