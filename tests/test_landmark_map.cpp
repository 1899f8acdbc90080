#include <catch2/catch.hpp>

#include "est/map/landmark_map.hpp"

TEST_CASE("landmark map keeps insertion order, refuses duplicates, NaN and overflow", "[landmark_map]") {
  static est::LandmarkMapStorage<3> m;
  CHECK(m.capacity() == 3);
  CHECK(m.add({1.0f, 2.0f, 10.0f}) == est::MapStatus::ok);
  CHECK(m.add({3.0f, 4.0f, 11.0f}) == est::MapStatus::ok);
  CHECK(m.add({5.0f, 6.0f, 10.0f}) == est::MapStatus::duplicate);
  CHECK(m.add({5.0f, __builtin_nanf(""), 12.0f}) == est::MapStatus::nonfinite);
  CHECK(m.add({5.0f, 6.0f, 12.0f}) == est::MapStatus::ok);
  CHECK(m.add({7.0f, 8.0f, 13.0f}) == est::MapStatus::full);
  const est::LandmarkMap v = m.view();
  CHECK(v.size() == 3);
  CHECK(v[1].x == 3.0f);
  CHECK(v.find_signature(12.0f) == 2);
  CHECK(v.find_signature(99.0f) == -1);
  CHECK(v.contains(2));
  CHECK_FALSE(v.contains(3));
  m.clear();
  CHECK(m.view().size() == 0);
  CHECK(m.add({5.0f, 6.0f, 10.0f}) == est::MapStatus::ok);
  CHECK(m.add({5.0f, 6.0f, 10.0f}, false) == est::MapStatus::ok);  // duplicates allowed on request
}
