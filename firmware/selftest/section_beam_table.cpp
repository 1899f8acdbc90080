#include "est/map/heading_range_table.hpp"
#include "est/map/occupancy_grid.hpp"
#include "est/map/ray_casting.hpp"
#include "est/math/inline_exp.hpp"
#include "est/math/log_product.hpp"
#include "est/random/xoshiro128.hpp"
#include "est/sensor/beam_range_finder_model_table.hpp"
#include "est/sensor/beam_readings.hpp"
#include "est/sensor/range_scan.hpp"
#include "est/util/digest.hpp"
#include "beam_room.hpp"
#include "selftest.hpp"

namespace est::selftest {
namespace {

// 6.4 m x 4.8 m at 0.1 m with a partition and a desk; 16 headings per cell (96 KiB).
OccupancyGridStorage<64, 48> g_room;
HeadingRangeTableStorage<64, 48, 16> g_table;
PreparedScan<72> g_scan72;
BeamBearingsStorage<72> g_bearings;
BeamReadingsStorage<72> g_readings;

}  // namespace

// The beam model's table path (Thrun table 6.1 over a heading range table): the table itself, the inline exp, the
// log of a product, the prepared readings and both table overloads.
std::uint64_t section_beam_table() {
  Digest d;
  Rng rng(20261124u);
  for (int i = 0; i < 512; ++i) {
    const float x = rng.uniform(-84.0f, 0.0f);
    d.add(imath::exp(x));
  }
  LogProduct q;
  for (int i = 0; i < 400; ++i) {
    q.mul(rng.uniform(0.0f, 4.0f));
    if (i % 50 == 49) d.add(q.log());
  }

  furnish_beam_room(g_room);
  const OccupancyGrid grid = g_room.grid();
  const GridRayCaster exact(grid);
  d.add_u32(static_cast<std::uint32_t>(g_table.build(grid, exact, 16, 6.0f)));
  const HeadingRangeTable table = g_table.view();
  for (std::uint32_t i = 0; i < HeadingRangeTableStorage<64, 48, 16>::kEntries; i += 13u) d.add_u32(table.data()[i]);

  const Pose2 truth{1.7f, 2.9f, 0.4f};
  beam_room_scan(grid, truth, rng, g_scan72);
  const ScanBeams b = g_scan72.beams();
  const BeamRangeFinderModel beam = beam_room_model();
  d.add_u32(g_bearings.prepare(b, table) ? 1u : 0u);
  d.add_u32(g_readings.prepare(b, beam) ? 1u : 0u);
  const BeamReadings readings = g_readings.view();
  for (std::int32_t k = 0; k < b.count; ++k) {
    d.add(readings.reading[k].short_num);
    d.add(beam.density(readings.reading[k], 2.5f));
  }
  for (int i = 0; i < 32; ++i) {
    const Pose2 x{truth.x + rng.uniform(-0.3f, 0.3f), truth.y + rng.uniform(-0.3f, 0.3f),
                  truth.theta + rng.uniform(-0.2f, 0.2f)};
    d.add(beam_range_finder_model(b, g_bearings.view(), x, {}, table, beam));
    d.add(beam_range_finder_model(b, g_bearings.view(), readings, x, {}, table, beam));
  }
  return d.value();
}

}  // namespace est::selftest
