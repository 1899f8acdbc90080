#include <catch2/catch.hpp>

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>
#include <unistd.h>

#include "datasets.hpp"
#include "maps/ros_map_loader.hpp"

namespace {

est::OccupancyGridStorage<1200, 1200> g_grid;

struct TempDir {
  std::string path;
  TempDir() {
    char tmpl[] = "/tmp/est_map_test_XXXXXX";
    const char* p = ::mkdtemp(tmpl);
    REQUIRE(p != nullptr);
    path = p;
  }
  ~TempDir() { std::system(("rm -rf '" + path + "'").c_str()); }
  std::string write(const std::string& name, const std::string& bytes) const {
    const std::string f = path + "/" + name;
    std::ofstream(f, std::ios::binary) << bytes;
    return f;
  }
};

// 3 x 2 image, top row first: occupied, free, unknown / free, free, occupied (trinary pixel values).
const std::string kP5 = std::string("P5\n# comment\n3 2\n255\n") + std::string("\x00\xfe\xcd\xfe\xfe\x00", 6);
const std::string kP2 = "P2\n3 2\n255\n0 254 205\n254 254 0\n";
const std::string kYaml =
    "image: map.pgm\nresolution: 0.1\norigin: [-1.0, 2.0, 0.0]\nnegate: 0\noccupied_thresh: 0.65\n"
    "free_thresh: 0.196\nmode: trinary\n";

std::string reason_of(const std::string& yaml, const std::string& pgm) {
  TempDir d;
  d.write("map.pgm", pgm);
  const std::string y = d.write("map.yaml", yaml);
  try {
    est::sim::load_ros_map(y, g_grid);
  } catch (const est::sim::MapLoadError& e) {
    return e.what();
  }
  return "accepted";
}

void check_small_map() {
  const est::OccupancyGrid g = g_grid.grid();
  REQUIRE(g.width() == 3);
  REQUIRE(g.height() == 2);
  CHECK(g.resolution() == 0.1f);
  CHECK(g.origin_x() == -1.0f);
  CHECK(g.origin_y() == 2.0f);
  // Image row 0 is the top: grid row 1.
  CHECK(g.classify(0, 1) == est::CellClass::occupied);
  CHECK(g.classify(1, 1) == est::CellClass::free);
  CHECK(g.classify(2, 1) == est::CellClass::unknown);
  CHECK(g.classify(0, 0) == est::CellClass::free);
  CHECK(g.classify(2, 0) == est::CellClass::occupied);
}

}  // namespace

TEST_CASE("a map_server YAML with a P5 or P2 image loads with the image's top row at the top", "[map_loader]") {
  CHECK(reason_of(kYaml, kP5) == "accepted");
  check_small_map();
  CHECK(reason_of(kYaml, kP2) == "accepted");
  check_small_map();
}

TEST_CASE("negate and scale modes follow map_server", "[map_loader]") {
  // negate: p = v / 255, so 0 is free and 254 occupied.
  std::string y = kYaml;
  y.replace(y.find("negate: 0"), 9, "negate: 1");
  REQUIRE(reason_of(y, kP5) == "accepted");
  CHECK(g_grid.grid().classify(0, 1) == est::CellClass::free);
  CHECK(g_grid.grid().classify(1, 1) == est::CellClass::occupied);
  // scale: between the thresholds, 99 (p - free) / (occ - free); v = 128 gives p = 127/255 = 0.498: 65.9, rounded to 66.
  std::string s = kYaml;
  s.replace(s.find("trinary"), 7, "scale");
  REQUIRE(reason_of(s, std::string("P5 1 1 255\n") + std::string("\x80", 1)) == "accepted");
  CHECK(g_grid.grid().at(0, 0) == 66);
}

TEST_CASE("malformed map files are rejected with their reason", "[map_loader]") {
  const struct {
    std::string yaml, pgm, reason;
  } cases[] = {
      {"resolution: 0.1\norigin: [0, 0, 0]\noccupied_thresh: 0.65\nfree_thresh: 0.2\n", kP5, "missing required key 'image'"},
      {"image: map.pgm\norigin: [0, 0, 0]\noccupied_thresh: 0.65\nfree_thresh: 0.2\n", kP5, "missing required key 'resolution'"},
      {"image: map.pgm\nresolution: abc\norigin: [0, 0, 0]\noccupied_thresh: 0.65\nfree_thresh: 0.2\n", kP5, "'resolution' is not a number"},
      {"image: map.pgm\nresolution: -0.1\norigin: [0, 0, 0]\noccupied_thresh: 0.65\nfree_thresh: 0.2\n", kP5, "'resolution' must be > 0"},
      {"image: map.pgm\nresolution: 0.1\norigin: [0, 0]\noccupied_thresh: 0.65\nfree_thresh: 0.2\n", kP5, "exactly 3 numbers"},
      {"image: map.pgm\nresolution: 0.1\norigin: [0, 0, 0.5]\noccupied_thresh: 0.65\nfree_thresh: 0.2\n", kP5, "origin yaw != 0"},
      {"image: map.pgm\nresolution: 0.1\norigin: [0, 0, 0]\noccupied_thresh: 0.1\nfree_thresh: 0.2\n", kP5, "free_thresh must be below"},
      {"image: map.pgm\nresolution: 0.1\norigin: [0, 0, 0]\noccupied_thresh: 1.5\nfree_thresh: 0.2\n", kP5, "thresholds must lie in [0, 1]"},
      {kYaml + "mode: fancy\n", kP5, "duplicate key 'mode'"},
      {"image: map.pgm\nresolution: 0.1\norigin: [0, 0, 0]\noccupied_thresh: 0.65\nfree_thresh: 0.2\nmode: fancy\n", kP5, "unknown 'mode'"},
      {"image: map.pgm\nresolution 0.1\n", kP5, "expected 'key: value'"},
      {"image: map.png\nresolution: 0.1\norigin: [0, 0, 0]\noccupied_thresh: 0.65\nfree_thresh: 0.2\n", kP5, "not a .pgm"},
      {"image: other.pgm\nresolution: 0.1\norigin: [0, 0, 0]\noccupied_thresh: 0.65\nfree_thresh: 0.2\n", kP5, "cannot open file"},
      {kYaml, "P6\n3 2\n255\nxxxxxxxxxxxxxxxxxx", "not a grey PGM"},
      {kYaml, std::string("P5\n3 2\n255\n\x00\x01", 13), "truncated PGM raster: 6 bytes expected, 2 present"},
      {kYaml, "P5\n3\n", "malformed PGM header"},
      {kYaml, "P5\n0 2\n255\n", "width and height must be positive"},
      {kYaml, "P2\n3 2\n100\n0 1 2 3 4 101\n", "pixel value above maxval"},
      {kYaml, "P2\n3 2\n255\n0 1 2 3\n", "truncated or non-numeric P2 raster"},
      {kYaml, "P5\n1300 2\n255\n" + std::string(2600, '\xfe'), "exceeds the grid capacity 1200 x 1200"},
      // Found by tests/fuzz/fuzz_ros_map: a short file claiming the largest image was allocated (512 MB) before its
      // raster was checked.
      {kYaml, "P5 16384 16384 65535\n\x01", "truncated PGM raster: 536870912 bytes expected, 1 present"},
      {kYaml, "P2 16384 16384 255\n0 0", "truncated or non-numeric P2 raster: 268435456 pixels expected"},
      {"image: map.pgm\nresolution: abc\n", kP5, "map.yaml:2: 'resolution' is not a number"},
  };
  for (const auto& c : cases) {
    const std::string why = reason_of(c.yaml, c.pgm);
    INFO("expected reason: " << c.reason << "\n     got: " << why);
    CHECK(why.find(c.reason) != std::string::npos);
  }
}

TEST_CASE("the Intel map loads as a trinary PGM at 0.05 m", "[map_loader][dataset]") {
  const std::string dir = test_support::dataset_or_skip("carmen-radish-logs") + "/..";
  est::sim::load_trinary_pgm_map(dir + "/carmen-radish-logs/occupancy-maps-gondsm/intel.pgm", g_grid);
  const est::OccupancyGrid g = g_grid.grid();
  REQUIRE(g.width() == 888);
  REQUIRE(g.height() == 848);
  CHECK(g.resolution() == 0.05f);
  long counts[3] = {0, 0, 0};
  for (std::int32_t y = 0; y < g.height(); ++y)
    for (std::int32_t x = 0; x < g.width(); ++x) ++counts[static_cast<int>(g.classify(x, y))];
  std::printf("intel.pgm: %ld free, %ld occupied, %ld unknown cells\n", counts[0], counts[1], counts[2]);
  CHECK(counts[0] + counts[1] + counts[2] == 888L * 848L);
  CHECK(counts[1] > 5000);   // walls exist
  CHECK(counts[0] > 100000); // a building's worth of free space
}
