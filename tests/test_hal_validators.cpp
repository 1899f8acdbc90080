// HAL sample validation: every bad-input class rejected with its reason counted, good input passed on unchanged.
#include <catch2/catch.hpp>
#include <cmath>
#include <limits>
#include <vector>

#include "hal/validated_inputs.hpp"

using hal::Fault;
using hal::TimeNs;
using hal::kNsPerMs;

namespace {

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
constexpr float kInf = std::numeric_limits<float>::infinity();

hal::WheelTicks ticks(TimeNs stamp, std::uint32_t left, std::uint32_t right) {
  hal::WheelTicks s;
  s.stamp_ns = stamp;
  s.wheel_count = 2;
  s.count[0] = left;
  s.count[1] = right;
  return s;
}

struct FakeClock final : hal::Clock {
  TimeNs now = 0;
  TimeNs now_ns() override { return now; }
};

struct Recorder final : hal::ValidatedSensorPort {
  std::vector<hal::WheelTickDelta> motion;
  std::vector<hal::SteeringSample> steering;
  std::vector<std::size_t> scans;
  std::vector<std::vector<hal::LandmarkFeature>> sightings;
  void on_wheel_motion(const hal::WheelTickDelta& d) override { motion.push_back(d); }
  void on_steering(const hal::SteeringSample& s) override { steering.push_back(s); }
  void on_range_scan(const hal::RangeScanView& s) override { scans.push_back(s.count); }
  void on_landmarks(const hal::LandmarkSightingView& s) override {
    sightings.emplace_back(s.features, s.features + s.count);
  }
};

hal::ScanGeometry lidar() { return {-1.5f, 0.01f, 0.1f, 30.0f, 0.1f}; }

}  // namespace

TEST_CASE("counter_delta takes the short way round a wrapping counter", "[hal][wheel]") {
  CHECK(hal::counter_delta(5, 65530, 16) == 11);      // forward through the wrap
  CHECK(hal::counter_delta(65530, 5, 16) == -11);     // backward through the wrap
  CHECK(hal::counter_delta(1000, 900, 16) == 100);
  CHECK(hal::counter_delta(0, 0x80000000u, 32) == std::numeric_limits<std::int32_t>::min());
  CHECK(hal::counter_delta(3, 0xFFFFFFFEu, 32) == 5);
  CHECK(hal::counter_delta(1, 4095, 12) == 2);         // a 12-bit counter wraps at 4096
  CHECK(hal::counter_delta(0, 2047, 12) == -2047);
  CHECK(hal::counter_delta(2047, 0, 12) == 2047);
  CHECK(hal::counter_delta(2048, 0, 12) == -2048);
}

TEST_CASE("wheel ticks through a 16-bit wrap give the exact increments", "[hal][wheel]") {
  hal::WheelTicksValidator v({2, 16, 20000, 500 * kNsPerMs, {}});
  hal::WheelTickDelta d;
  REQUIRE(v.check(ticks(0, 65500, 100), 0, d) == Fault::none);
  CHECK(d.dt_ns == 0);
  CHECK(d.ticks[0] == 0);
  // 10 ms later: left +100 across the wrap (65500 -> 64), right -150 across zero (100 -> 65486).
  REQUIRE(v.check(ticks(10 * kNsPerMs, 64, 65486), 10 * kNsPerMs, d) == Fault::none);
  CHECK(d.dt_ns == 10 * kNsPerMs);
  CHECK(d.ticks[0] == 100);
  CHECK(d.ticks[1] == -150);
  CHECK(v.faults().total() == 0);
}

TEST_CASE("wheel ticks faster than the limit are out of range and become the new reference", "[hal][wheel]") {
  hal::WheelTicksValidator v({2, 16, 20000, 500 * kNsPerMs, {}});  // 200 ticks per 10 ms at most
  hal::WheelTickDelta d;
  REQUIRE(v.check(ticks(0, 0, 0), 0, d) == Fault::none);
  CHECK(v.check(ticks(10 * kNsPerMs, 201, 0), 10 * kNsPerMs, d) == Fault::out_of_range);
  CHECK(v.faults()[Fault::out_of_range] == 1);
  REQUIRE(v.check(ticks(20 * kNsPerMs, 301, 10), 20 * kNsPerMs, d) == Fault::none);
  CHECK(d.ticks[0] == 100);  // from the rejected sample, not from 0
  CHECK(d.ticks[1] == 10);
  CHECK(v.check(ticks(30 * kNsPerMs, 70000, 10), 30 * kNsPerMs, d) == Fault::out_of_range);  // > 16 bits
  hal::WheelTicks three = ticks(40 * kNsPerMs, 1, 1);
  three.wheel_count = 3;
  CHECK(v.check(three, 40 * kNsPerMs, d) == Fault::out_of_range);
  CHECK(v.faults()[Fault::out_of_range] == 3);
}

TEST_CASE("timing faults: backwards, duplicate, stale, from the future", "[hal][timing]") {
  hal::WheelTicksValidator v({2, 16, 20000, 500 * kNsPerMs, {200 * kNsPerMs, 5 * kNsPerMs}});
  hal::WheelTickDelta d;
  REQUIRE(v.check(ticks(1000 * kNsPerMs, 0, 0), 1000 * kNsPerMs, d) == Fault::none);
  CHECK(v.check(ticks(990 * kNsPerMs, 1, 1), 1000 * kNsPerMs, d) == Fault::time_backwards);
  CHECK(v.check(ticks(1000 * kNsPerMs, 1, 1), 1000 * kNsPerMs, d) == Fault::duplicate);
  CHECK(v.check(ticks(1001 * kNsPerMs, 1, 1), 1202 * kNsPerMs, d) == Fault::stale);
  CHECK(v.check(ticks(1010 * kNsPerMs, 1, 1), 1004 * kNsPerMs, d) == Fault::from_future);
  CHECK(v.faults()[Fault::time_backwards] == 1);
  CHECK(v.faults()[Fault::duplicate] == 1);
  CHECK(v.faults()[Fault::stale] == 1);
  CHECK(v.faults()[Fault::from_future] == 1);
  CHECK(v.faults().total() == 4);
  // The reference did not move: the next good sample measures from 1000 ms.
  REQUIRE(v.check(ticks(1010 * kNsPerMs, 5, 6), 1010 * kNsPerMs, d) == Fault::none);
  CHECK(d.dt_ns == 10 * kNsPerMs);
  CHECK(d.ticks[0] == 5);
}

TEST_CASE("timestamps at the ends of the int64 range are stale or from the future, without overflow",
          "[hal][timing]") {
  hal::SteeringValidator v;
  CHECK(v.check({INT64_MIN, 0.0f}, 1000) == Fault::stale);
  CHECK(v.check({INT64_MAX, 0.0f}, 1000) == Fault::from_future);
  CHECK(v.check({INT64_MIN, 0.0f}, INT64_MAX) == Fault::stale);
  CHECK(v.check({INT64_MAX, 0.0f}, INT64_MIN) == Fault::from_future);
  CHECK(v.check({-5, 0.0f}, -5) == Fault::none);
}

TEST_CASE("after a gap longer than max_gap the encoders start afresh instead of guessing whole turns",
          "[hal][wheel]") {
  hal::WheelTicksLimits limits;
  limits.max_gap_ns = 500 * kNsPerMs;
  limits.timing.max_age_ns = 10 * hal::kNsPerS;
  hal::WheelTicksValidator v(limits);
  hal::WheelTickDelta d;
  REQUIRE(v.check(ticks(0, 100, 100), 0, d) == Fault::none);
  REQUIRE(v.check(ticks(600 * kNsPerMs, 5000, 100), 600 * kNsPerMs, d) == Fault::none);
  CHECK(d.dt_ns == 0);
  CHECK(d.ticks[0] == 0);
  REQUIRE(v.check(ticks(610 * kNsPerMs, 5100, 100), 610 * kNsPerMs, d) == Fault::none);
  CHECK(d.ticks[0] == 100);
}

TEST_CASE("steering: NaN, infinity and beyond the mechanical limit are rejected", "[hal][steering]") {
  hal::SteeringValidator v({0.6f, {}});
  CHECK(v.check({0, kNaN}, 0) == Fault::not_finite);
  CHECK(v.check({0, kInf}, 0) == Fault::not_finite);
  CHECK(v.check({0, -kInf}, 0) == Fault::not_finite);
  CHECK(v.check({0, 0.61f}, 0) == Fault::out_of_range);
  CHECK(v.check({0, -0.61f}, 0) == Fault::out_of_range);
  CHECK(v.check({0, 0.6f}, 0) == Fault::none);
  CHECK(v.check({0, 0.1f}, 0) == Fault::duplicate);
  CHECK(v.faults()[Fault::not_finite] == 3);
  CHECK(v.faults()[Fault::out_of_range] == 2);
  CHECK(v.faults()[Fault::duplicate] == 1);
}

TEST_CASE("beams: hits, max-range readings (+inf too) and unusable readings", "[hal][scan]") {
  const hal::ScanGeometry g = lidar();
  CHECK(hal::classify_beam(5.0f, g) == hal::BeamClass::hit);
  CHECK(hal::classify_beam(0.1f, g) == hal::BeamClass::hit);
  CHECK(hal::classify_beam(30.0f, g) == hal::BeamClass::max_range);
  CHECK(hal::classify_beam(kInf, g) == hal::BeamClass::max_range);
  CHECK(hal::classify_beam(kNaN, g) == hal::BeamClass::unusable);
  CHECK(hal::classify_beam(-kInf, g) == hal::BeamClass::unusable);
  CHECK(hal::classify_beam(0.05f, g) == hal::BeamClass::unusable);
}

TEST_CASE("scans: bad geometry, NaN fields, too many beams and too few valid beams are rejected", "[hal][scan]") {
  hal::RangeScanValidator v({100, 10, 100.0f, 1.0f, {}});
  std::vector<float> r(50, 5.0f);
  hal::RangeScanView s{0, lidar(), r.data(), r.size()};
  REQUIRE(v.check(s, 0) == Fault::none);

  auto with = [&](auto change) {
    hal::RangeScanView c = s;
    c.stamp_ns = s.stamp_ns + 1;
    change(c);
    return v.check(c, c.stamp_ns);
  };
  CHECK(with([](hal::RangeScanView& c) { c.geometry.angle_min_rad = kNaN; }) == Fault::not_finite);
  CHECK(with([](hal::RangeScanView& c) { c.geometry.range_max_m = kInf; }) == Fault::not_finite);
  CHECK(with([](hal::RangeScanView& c) { c.geometry.angle_increment_rad = 0.0f; }) == Fault::bad_geometry);
  CHECK(with([](hal::RangeScanView& c) { c.geometry.range_max_m = 0.05f; }) == Fault::bad_geometry);
  CHECK(with([](hal::RangeScanView& c) { c.geometry.range_min_m = -1.0f; }) == Fault::bad_geometry);
  CHECK(with([](hal::RangeScanView& c) { c.geometry.range_max_m = 101.0f; }) == Fault::bad_geometry);
  CHECK(with([](hal::RangeScanView& c) { c.geometry.angle_increment_rad = 0.2f; }) == Fault::bad_geometry);  // 9.8 rad fan
  CHECK(with([](hal::RangeScanView& c) { c.count = 101; }) == Fault::out_of_range);
  CHECK(with([](hal::RangeScanView& c) { c.count = 0; }) == Fault::out_of_range);
  CHECK(v.faults()[Fault::not_finite] == 2);
  CHECK(v.faults()[Fault::bad_geometry] == 5);
  CHECK(v.faults()[Fault::out_of_range] == 2);

  // 41 NaN or too-short beams out of 50 leave 9 usable beams: below the limit of 10.
  std::vector<float> bad(50, kNaN);
  for (std::size_t i = 0; i < 20; ++i) bad[i] = 0.01f;
  for (std::size_t i = 41; i < 50; ++i) bad[i] = (i % 2) ? kInf : 7.0f;
  hal::RangeScanView b{10, lidar(), bad.data(), bad.size()};
  CHECK(v.check(b, 10) == Fault::too_few_valid_beams);
  CHECK(v.beams().not_a_number == 21);
  CHECK(v.beams().below_min == 20);
  bad[40] = 3.0f;  // 10 usable
  CHECK(v.check(b, 10) == Fault::none);
}

TEST_CASE("ValidatedInputs passes good samples on and counts every reject by reason", "[hal][gate]") {
  FakeClock clock;
  Recorder out;
  hal::InputLimits limits;
  limits.scan.min_valid_beams = 1;
  hal::ValidatedInputs in(limits, clock, out);

  clock.now = 100 * kNsPerMs;
  in.on_wheel_ticks(ticks(100 * kNsPerMs, 10, 10));
  in.on_wheel_ticks(ticks(90 * kNsPerMs, 12, 12));   // backwards
  in.on_steering({100 * kNsPerMs, 0.2f});
  in.on_steering({101 * kNsPerMs, kNaN});
  float ranges[3] = {1.0f, 2.0f, 3.0f};
  in.on_range_scan({100 * kNsPerMs, lidar(), ranges, 3});
  in.on_range_scan({100 * kNsPerMs, lidar(), ranges, 3});  // duplicate
  clock.now = 1000 * kNsPerMs;
  in.on_steering({110 * kNsPerMs, 0.1f});  // stale

  CHECK(out.motion.size() == 1);
  CHECK(out.steering.size() == 1);
  CHECK(out.scans.size() == 1);
  const hal::FaultCounters f = in.faults();
  CHECK(f[Fault::time_backwards] == 1);
  CHECK(f[Fault::not_finite] == 1);
  CHECK(f[Fault::duplicate] == 1);
  CHECK(f[Fault::stale] == 1);
  CHECK(f.total() == 4);
}

TEST_CASE("landmark sightings: bad features are dropped and counted, the good ones pass with the stamp",
          "[hal][landmarks]") {
  hal::LandmarkLimits limits;
  limits.max_range_m = 20.0f;
  limits.max_id = 99;
  hal::LandmarkValidator v(limits);
  hal::LandmarkSighting<hal::kMaxLandmarkFeatures> out;
  const hal::LandmarkFeature f[9] = {
      {3.0f, 0.5f, 1.0f, 2},      // good, known correspondence
      {kNaN, 0.5f, 1.0f, 2},      // not finite
      {3.0f, kInf, 1.0f, -1},     // not finite
      {3.0f, 0.5f, kNaN, -1},     // not finite signature
      {-1.0f, 0.5f, 1.0f, -1},    // negative range
      {25.0f, 0.5f, 1.0f, -1},    // beyond the sensor's reach
      {3.0f, 3.5f, 1.0f, -1},     // bearing outside (-pi, pi]
      {3.0f, 0.5f, 1.0f, 100},    // no such map index
      {19.0f, -3.1f, 0.0f, -1}};  // good, correspondence unknown
  REQUIRE(v.check({100 * kNsPerMs, f, 9}, 100 * kNsPerMs, out) == Fault::none);
  REQUIRE(out.count == 2u);
  CHECK(out.stamp_ns == 100 * kNsPerMs);
  CHECK(out.features[0].id == 2);
  CHECK(out.features[1].range_m == 19.0f);
  CHECK(v.faults()[Fault::not_finite] == 3);
  CHECK(v.faults()[Fault::out_of_range] == 4);
  CHECK(v.features_accepted() == 2u);

  // Whole sightings: empty, too many, no pointer, timing, nothing good left.
  CHECK(v.check({110 * kNsPerMs, f, 0}, 110 * kNsPerMs, out) == Fault::out_of_range);
  CHECK(v.check({110 * kNsPerMs, f, hal::kMaxLandmarkFeatures + 1}, 110 * kNsPerMs, out) == Fault::out_of_range);
  CHECK(v.check({110 * kNsPerMs, nullptr, 1}, 110 * kNsPerMs, out) == Fault::out_of_range);
  CHECK(v.check({100 * kNsPerMs, f, 1}, 110 * kNsPerMs, out) == Fault::duplicate);
  CHECK(v.check({90 * kNsPerMs, f, 1}, 110 * kNsPerMs, out) == Fault::time_backwards);
  CHECK(v.check({1000 * kNsPerMs, f, 1}, 110 * kNsPerMs, out) == Fault::from_future);
  CHECK(v.check({110 * kNsPerMs, f + 1, 1}, 2000 * kNsPerMs, out) == Fault::stale);
  CHECK(v.check({120 * kNsPerMs, f + 1, 2}, 120 * kNsPerMs, out) == Fault::out_of_range);
  CHECK(out.count == 0u);
  CHECK(v.faults()[Fault::not_finite] == 5);  // the last sighting's two features
  CHECK(v.faults().total() == 3 + 4 + 3 + 4 + 2);
}

TEST_CASE("ValidatedInputs passes checked landmark sightings on and counts their faults", "[hal][gate]") {
  FakeClock clock;
  Recorder out;
  hal::ValidatedInputs in(hal::InputLimits{}, clock, out);
  clock.now = 100 * kNsPerMs;
  const hal::LandmarkFeature f[2] = {{3.0f, 0.5f, 1.0f, 2}, {kNaN, 0.5f, 1.0f, 2}};
  in.on_landmarks({100 * kNsPerMs, f, 2});
  in.on_landmarks({100 * kNsPerMs, f, 2});  // duplicate
  REQUIRE(out.sightings.size() == 1u);
  REQUIRE(out.sightings[0].size() == 1u);
  CHECK(out.sightings[0][0].range_m == 3.0f);
  CHECK(in.faults()[Fault::not_finite] == 1);
  CHECK(in.faults()[Fault::duplicate] == 1);
  CHECK(in.landmarks().faults().total() == 2);
}

TEST_CASE("fault counters saturate instead of wrapping", "[hal]") {
  hal::FaultCounters c;
  c.count[static_cast<std::size_t>(Fault::stale)] = UINT32_MAX - 1;
  c.add(Fault::stale);
  c.add(Fault::stale);
  CHECK(c[Fault::stale] == UINT32_MAX);
  c.add(Fault::duplicate);
  CHECK(c.total() == UINT32_MAX);
  CHECK(std::string(hal::to_string(Fault::too_few_valid_beams)) == "too_few_valid_beams");
}
