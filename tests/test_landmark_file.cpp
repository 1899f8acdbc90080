// Landmark maps for host programs (hal/maps/landmark_file.hpp): the office's posts, and CSV files whose every bad
// line is refused with the file, the line number and the reason.
#include <catch2/catch.hpp>

#include <cstdio>
#include <fstream>
#include <stdexcept>
#include <string>
#include <unistd.h>

#include "hal/maps/landmark_file.hpp"
#include "world/office_map.hpp"

namespace {

std::string write_file(const std::string& text) {
  static int n = 0;
  const std::string path = "/tmp/est_landmarks_" + std::to_string(::getpid()) + "_" + std::to_string(n++) + ".csv";
  std::ofstream(path) << text;
  return path;
}

std::string error_of(const std::string& text) {
  const std::string path = write_file(text);
  est::LandmarkMapStorage<8> map;
  try {
    hal::maps::load_landmark_csv(path, map);
  } catch (const std::runtime_error& e) {
    std::remove(path.c_str());
    return e.what();
  }
  std::remove(path.c_str());
  return "";
}

}  // namespace

TEST_CASE("the office landmarks are 16 posts with signatures 1..16", "[landmark_file]") {
  est::LandmarkMapStorage<32> map;
  est::sim::make_office_landmarks(map);
  REQUIRE(map.size() == 16);
  for (std::int32_t j = 0; j < 16; ++j) {
    CHECK(map.view()[j].signature == static_cast<float>(j + 1));
    CHECK(map.view()[j].x >= 0.0f);
    CHECK(map.view()[j].x <= 20.0f);
    CHECK(map.view()[j].y >= 0.0f);
    CHECK(map.view()[j].y <= 15.0f);
  }
  CHECK(map.view()[0].x == 0.5f);
  CHECK(map.view()[15].y == 5.0f);
}

TEST_CASE("a landmark CSV loads in line order, comments and blank lines skipped", "[landmark_file]") {
  const std::string path = write_file("# x, y, signature\n1.5, -2.25, 7\n\n  3,4,8\r\n# end\n-1e1,0.5,9");
  est::LandmarkMapStorage<8> map;
  hal::maps::load_landmark_csv(path, map);
  std::remove(path.c_str());
  REQUIRE(map.size() == 3);
  CHECK(map.view()[0].x == 1.5f);
  CHECK(map.view()[0].y == -2.25f);
  CHECK(map.view()[0].signature == 7.0f);
  CHECK(map.view()[1].x == 3.0f);
  CHECK(map.view()[2].x == -10.0f);
}

TEST_CASE("bad landmark files are refused with the line and the reason", "[landmark_file]") {
  using Catch::Matchers::Contains;
  CHECK_THAT(error_of("1,2\n"), Contains(":1: expected x,y,signature"));
  CHECK_THAT(error_of("1,2,3\n1,x,3\n"), Contains(":2: expected x,y,signature"));
  CHECK_THAT(error_of("1,2,3,4\n"), Contains(":1: unexpected text"));
  CHECK_THAT(error_of("1,2,3\n4,5,3\n"), Contains(":2: a signature appears twice"));
  CHECK_THAT(error_of("nan,2,3\n"), Contains(":1: a coordinate or signature is not finite"));
  CHECK_THAT(error_of("1e999,2,3\n"), Contains(":1: expected x,y,signature"));
  CHECK_THAT(error_of("# nothing\n\n"), Contains("no landmarks"));
  CHECK_THAT(error_of("0,0,1\n0,0,2\n0,0,3\n0,0,4\n0,0,5\n0,0,6\n0,0,7\n0,0,8\n0,0,9\n"),
             Contains(":9: more landmarks than the map holds"));
  est::LandmarkMapStorage<8> map;
  CHECK_THROWS_WITH(hal::maps::load_landmark_csv("/nonexistent/landmarks.csv", map), Contains("cannot open"));
}
