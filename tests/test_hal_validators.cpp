// HAL sample validation: every bad-input class rejected with its reason counted, good input passed on unchanged;
// odometry poses differenced into increments (across the wrap of the bus's counters), twists checked against the
// base's limits.
#include <catch2/catch.hpp>
#include <cmath>
#include <limits>
#include <vector>

#include "hal/sensors/odometry/can.hpp"
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

struct Recorder final : hal::PortImplementation<Recorder, hal::ValidatedSensorPort> {
  std::vector<hal::WheelTickDelta> motion;
  std::vector<hal::SteeringSample> steering;
  std::vector<hal::TwistSample> twists;
  std::vector<hal::OdometryDelta> odometry;
  std::vector<std::size_t> scans;
  std::vector<std::vector<hal::LandmarkFeature>> sightings;
  void handle(const hal::WheelTickDelta& d) { motion.push_back(d); }
  void handle(const hal::SteeringSample& s) { steering.push_back(s); }
  void handle(const hal::TwistSample& s) { twists.push_back(s); }
  void handle(const hal::OdometryDelta& d) { odometry.push_back(d); }
  void handle(const hal::RangeScanView& s) { scans.push_back(s.count); }
  void handle(const hal::LandmarkSightingView& s) { sightings.emplace_back(s.features, s.features + s.count); }
};

// The validators' check with the output discarded: the fault is what these cases look at.
template <typename Validator, typename Raw>
Fault check(Validator& v, const Raw& sample, TimeNs now) {
  typename hal::Validation<Raw>::Checked out{};
  return v.check(sample, now, out);
}

hal::OdometrySample odom(TimeNs stamp, float x, float y, float theta, float wrap = 0.0f) {
  hal::OdometrySample s;
  s.stamp_ns = stamp;
  s.pose = {x, y, theta};
  s.wrap_m = wrap;
  return s;
}

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
  CHECK(check(v, hal::SteeringSample{INT64_MIN, 0.0f}, 1000) == Fault::stale);
  CHECK(check(v, hal::SteeringSample{INT64_MAX, 0.0f}, 1000) == Fault::from_future);
  CHECK(check(v, hal::SteeringSample{INT64_MIN, 0.0f}, INT64_MAX) == Fault::stale);
  CHECK(check(v, hal::SteeringSample{INT64_MAX, 0.0f}, INT64_MIN) == Fault::from_future);
  CHECK(check(v, hal::SteeringSample{-5, 0.0f}, -5) == Fault::none);
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
  CHECK(check(v, hal::SteeringSample{0, kNaN}, 0) == Fault::not_finite);
  CHECK(check(v, hal::SteeringSample{0, kInf}, 0) == Fault::not_finite);
  CHECK(check(v, hal::SteeringSample{0, -kInf}, 0) == Fault::not_finite);
  CHECK(check(v, hal::SteeringSample{0, 0.61f}, 0) == Fault::out_of_range);
  CHECK(check(v, hal::SteeringSample{0, -0.61f}, 0) == Fault::out_of_range);
  CHECK(check(v, hal::SteeringSample{0, 0.6f}, 0) == Fault::none);
  CHECK(check(v, hal::SteeringSample{0, 0.1f}, 0) == Fault::duplicate);
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
  REQUIRE(check(v, s, 0) == Fault::none);

  auto with = [&](auto change) {
    hal::RangeScanView c = s;
    c.stamp_ns = s.stamp_ns + 1;
    change(c);
    return check(v, c, c.stamp_ns);
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
  CHECK(check(v, b, 10) == Fault::too_few_valid_beams);
  CHECK(v.beams().not_a_number == 21);
  CHECK(v.beams().below_min == 20);
  bad[40] = 3.0f;  // 10 usable
  CHECK(check(v, b, 10) == Fault::none);
}

TEST_CASE("ValidatedInputs passes good samples on and counts every reject by reason", "[hal][gate]") {
  FakeClock clock;
  Recorder out;
  hal::InputLimits limits;
  limits.scan.min_valid_beams = 1;
  hal::ValidatedInputs in(limits, clock, out);

  clock.now = 100 * kNsPerMs;
  in.on(ticks(100 * kNsPerMs, 10, 10));
  in.on(ticks(90 * kNsPerMs, 12, 12));   // backwards
  in.on(hal::SteeringSample{100 * kNsPerMs, 0.2f});
  in.on(hal::SteeringSample{101 * kNsPerMs, kNaN});
  float ranges[3] = {1.0f, 2.0f, 3.0f};
  in.on(hal::RangeScanView{100 * kNsPerMs, lidar(), ranges, 3});
  in.on(hal::RangeScanView{100 * kNsPerMs, lidar(), ranges, 3});  // duplicate
  clock.now = 1000 * kNsPerMs;
  in.on(hal::SteeringSample{110 * kNsPerMs, 0.1f});  // stale

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
  hal::LandmarkSightingView out;
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
  out = {};
  CHECK(v.check({120 * kNsPerMs, f + 1, 2}, 120 * kNsPerMs, out) == Fault::out_of_range);
  CHECK(out.count == 0u);  // a rejected sighting hands nothing on
  CHECK(v.faults()[Fault::not_finite] == 5);  // the last sighting's two features
  CHECK(v.faults().total() == 3 + 4 + 3 + 4 + 2);
}

TEST_CASE("ValidatedInputs passes checked landmark sightings on and counts their faults", "[hal][gate]") {
  FakeClock clock;
  Recorder out;
  hal::ValidatedInputs in(hal::InputLimits{}, clock, out);
  clock.now = 100 * kNsPerMs;
  const hal::LandmarkFeature f[2] = {{3.0f, 0.5f, 1.0f, 2}, {kNaN, 0.5f, 1.0f, 2}};
  in.on(hal::LandmarkSightingView{100 * kNsPerMs, f, 2});
  in.on(hal::LandmarkSightingView{100 * kNsPerMs, f, 2});  // duplicate
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

TEST_CASE("twists: NaN, infinity and speeds or turn rates beyond the base's limits are rejected, each counted",
          "[hal][twist]") {
  hal::TwistLimits limits;
  limits.max_speed_mps = 2.0f;
  limits.max_turn_rate_rps = 3.0f;
  hal::TwistValidator v(limits);
  hal::TwistSample out;
  CHECK(v.check({0, kNaN, 0.0f, 0.0f}, 0, out) == Fault::not_finite);
  CHECK(v.check({0, 0.0f, kInf, 0.0f}, 0, out) == Fault::not_finite);
  CHECK(v.check({0, 0.0f, 0.0f, -kInf}, 0, out) == Fault::not_finite);
  CHECK(v.check({0, 2.01f, 0.0f, 0.0f}, 0, out) == Fault::out_of_range);
  CHECK(v.check({0, 0.0f, -2.01f, 0.0f}, 0, out) == Fault::out_of_range);
  CHECK(v.check({0, 0.0f, 0.0f, 3.01f}, 0, out) == Fault::out_of_range);
  CHECK(v.check({0, 0.0f, 0.0f, -3.01f}, 0, out) == Fault::out_of_range);
  // At the limits: accepted, and handed on unchanged.
  REQUIRE(v.check({10, -2.0f, 2.0f, 3.0f}, 10, out) == Fault::none);
  CHECK(out.stamp_ns == 10);
  CHECK(out.v1_mps == -2.0f);
  CHECK(out.v2_mps == 2.0f);
  CHECK(out.w_rps == 3.0f);
  CHECK(v.faults()[Fault::not_finite] == 3);
  CHECK(v.faults()[Fault::out_of_range] == 4);
  CHECK(v.faults().total() == 7);
}

TEST_CASE("twists: timing faults are counted and leave the reference where it was", "[hal][twist]") {
  hal::TwistValidator v({5.0f, 10.0f, {200 * kNsPerMs, 5 * kNsPerMs}});
  hal::TwistSample out;
  REQUIRE(v.check({1000 * kNsPerMs, 0.5f, 0.0f, 0.1f}, 1000 * kNsPerMs, out) == Fault::none);
  CHECK(v.check({990 * kNsPerMs, 0.5f, 0.0f, 0.1f}, 1000 * kNsPerMs, out) == Fault::time_backwards);
  CHECK(v.check({1000 * kNsPerMs, 0.5f, 0.0f, 0.1f}, 1000 * kNsPerMs, out) == Fault::duplicate);
  CHECK(v.check({1001 * kNsPerMs, 0.5f, 0.0f, 0.1f}, 1202 * kNsPerMs, out) == Fault::stale);
  CHECK(v.check({1010 * kNsPerMs, 0.5f, 0.0f, 0.1f}, 1004 * kNsPerMs, out) == Fault::from_future);
  CHECK(v.faults()[Fault::time_backwards] == 1);
  CHECK(v.faults()[Fault::duplicate] == 1);
  CHECK(v.faults()[Fault::stale] == 1);
  CHECK(v.faults()[Fault::from_future] == 1);
  CHECK(v.check({1001 * kNsPerMs, 0.5f, 0.0f, 0.1f}, 1001 * kNsPerMs, out) == Fault::none);
}

TEST_CASE("odometry poses become increments in the previous pose's frame; the first is the reference",
          "[hal][odometry]") {
  hal::OdometryValidator v;
  hal::OdometryDelta d;
  const float half_pi = 0.5f * est::kPi;
  REQUIRE(v.check(odom(0, 1.0f, 2.0f, half_pi), 0, d) == Fault::none);
  CHECK(d.stamp_ns == 0);
  CHECK(d.dt_ns == 0);
  CHECK(d.increment.is_identity());
  CHECK(d.source.pose.y == 2.0f);
  // Facing +y, the robot moved 0.03 m along +y and 0.01 m along -x, and turned 0.1 rad: forward 0.03, left 0.01.
  REQUIRE(v.check(odom(20 * kNsPerMs, 0.99f, 2.03f, half_pi + 0.1f), 20 * kNsPerMs, d) == Fault::none);
  CHECK(d.dt_ns == 20 * kNsPerMs);
  CHECK(d.increment.x == Approx(0.03).margin(1e-6));
  CHECK(d.increment.y == Approx(0.01).margin(1e-6));
  CHECK(d.increment.theta == Approx(0.1).margin(1e-6));
  CHECK(d.source.pose.x == 0.99f);  // what a recorder writes, so that a replay differences the same poses
  // The increment composed onto the previous pose gives the new one (Thrun table 5.6's relative motion).
  const est::Pose2 again = est::compose({1.0f, 2.0f, half_pi}, d.increment);
  CHECK(again.x == Approx(0.99).margin(1e-6));
  CHECK(again.y == Approx(2.03).margin(1e-6));
  CHECK(again.theta == Approx(half_pi + 0.1f).margin(1e-6));
  CHECK(v.faults().total() == 0);
}

TEST_CASE("odometry: NaN, infinity, positions beyond the coordinate range and impossible headings are rejected",
          "[hal][odometry]") {
  hal::OdometryLimits limits;
  limits.max_coordinate_m = 100.0f;
  hal::OdometryValidator v(limits);
  hal::OdometryDelta d;
  CHECK(v.check(odom(0, kNaN, 0.0f, 0.0f), 0, d) == Fault::not_finite);
  CHECK(v.check(odom(0, 0.0f, kInf, 0.0f), 0, d) == Fault::not_finite);
  CHECK(v.check(odom(0, 0.0f, 0.0f, kNaN), 0, d) == Fault::not_finite);
  CHECK(v.check(odom(0, 0.0f, 0.0f, 0.0f, kInf), 0, d) == Fault::not_finite);
  CHECK(v.check(odom(0, 100.5f, 0.0f, 0.0f), 0, d) == Fault::out_of_range);
  CHECK(v.check(odom(0, 0.0f, -100.5f, 0.0f), 0, d) == Fault::out_of_range);
  CHECK(v.check(odom(0, 0.0f, 0.0f, 7.5f), 0, d) == Fault::out_of_range);
  CHECK(v.check(odom(0, 0.0f, 0.0f, 0.0f, -1.0f), 0, d) == Fault::out_of_range);  // a negative period
  CHECK(v.faults()[Fault::not_finite] == 4);
  CHECK(v.faults()[Fault::out_of_range] == 4);
  // Timing, as every sensor's.
  REQUIRE(v.check(odom(1000 * kNsPerMs, 0.0f, 0.0f, 0.0f), 1000 * kNsPerMs, d) == Fault::none);
  CHECK(v.check(odom(990 * kNsPerMs, 0.0f, 0.0f, 0.0f), 1000 * kNsPerMs, d) == Fault::time_backwards);
  CHECK(v.check(odom(1000 * kNsPerMs, 0.0f, 0.0f, 0.0f), 1000 * kNsPerMs, d) == Fault::duplicate);
  CHECK(v.check(odom(1001 * kNsPerMs, 0.0f, 0.0f, 0.0f), 1202 * kNsPerMs, d) == Fault::stale);
  CHECK(v.check(odom(1010 * kNsPerMs, 0.0f, 0.0f, 0.0f), 1004 * kNsPerMs, d) == Fault::from_future);
  CHECK(v.faults().total() == 12);
}

TEST_CASE("odometry from the bus is differenced across the wrap of its 18-bit counters and of the heading",
          "[hal][odometry]") {
  hal::OdometryValidator v;
  hal::OdometryDelta d;
  auto bus = [](TimeNs t, std::uint32_t x_mm, std::uint32_t y_mm, std::uint16_t theta) {
    hal::can::OdometryMsg m;
    m.x_mm = x_mm;
    m.y_mm = y_mm;
    m.theta = theta;
    return hal::can::to_sample(m, t);
  };
  REQUIRE(v.check(bus(0, 262100u, 10u, 0u), 0, d) == Fault::none);
  // x: 262100 -> 50 is +94 mm through the wrap; y: 10 -> 262140 is -14 mm through zero.
  REQUIRE(v.check(bus(40 * kNsPerMs, 50u, 262140u, 0u), 40 * kNsPerMs, d) == Fault::none);
  CHECK(d.increment.x == Approx(0.094).margin(2e-5));
  CHECK(d.increment.y == Approx(-0.014).margin(2e-5));
  CHECK(d.increment.theta == 0.0f);
  // The heading through one full turn: 65500 -> 36 is +72 steps of 2 pi / 65536.
  REQUIRE(v.check(bus(50 * kNsPerMs, 50u, 262140u, 65500u), 50 * kNsPerMs, d) == Fault::none);
  REQUIRE(v.check(bus(60 * kNsPerMs, 50u, 262140u, 36u), 60 * kNsPerMs, d) == Fault::none);
  CHECK(d.increment.theta == Approx(72.0 * 2.0 * M_PI / 65536.0).margin(1e-5));
  CHECK(d.increment.x == Approx(0.0).margin(1e-6));
  CHECK(v.faults().total() == 0);
}

TEST_CASE("an odometry jump is out of range and becomes the new reference; a gap or a new period starts afresh",
          "[hal][odometry]") {
  hal::OdometryLimits limits;  // 5 m/s, 10 rad/s
  limits.timing.max_age_ns = 10 * hal::kNsPerS;
  hal::OdometryValidator v(limits);
  hal::OdometryDelta d;
  REQUIRE(v.check(odom(0, 0.0f, 0.0f, 0.0f), 0, d) == Fault::none);
  CHECK(v.check(odom(10 * kNsPerMs, 1.0f, 0.0f, 0.0f), 10 * kNsPerMs, d) == Fault::out_of_range);  // 100 m/s: a reset
  REQUIRE(v.check(odom(20 * kNsPerMs, 1.02f, 0.0f, 0.0f), 20 * kNsPerMs, d) == Fault::none);
  CHECK(d.increment.x == Approx(0.02).margin(1e-6));  // from the rejected pose, not from the origin
  CHECK(d.dt_ns == 10 * kNsPerMs);
  CHECK(v.check(odom(30 * kNsPerMs, 1.02f, 0.0f, 0.2f), 30 * kNsPerMs, d) == Fault::out_of_range);  // 20 rad/s
  REQUIRE(v.check(odom(40 * kNsPerMs, 1.02f, 0.0f, 0.25f), 40 * kNsPerMs, d) == Fault::none);
  CHECK(d.increment.theta == Approx(0.05).margin(1e-6));
  CHECK(v.faults()[Fault::out_of_range] == 2);
  // After a gap longer than max_gap the motion is unknown: the sample is a new reference, not a 2 m jump.
  REQUIRE(v.check(odom(1000 * kNsPerMs, 3.0f, 0.0f, 0.25f), 1000 * kNsPerMs, d) == Fault::none);
  CHECK(d.increment.is_identity());
  CHECK(d.dt_ns == 0);
  // A source that switches to wrapping counters (another period) is not differenced against the old one either.
  REQUIRE(v.check(odom(1010 * kNsPerMs, 200.0f, 0.0f, 0.25f, 262.144f), 1010 * kNsPerMs, d) == Fault::none);
  CHECK(d.increment.is_identity());
  REQUIRE(v.check(odom(1020 * kNsPerMs, 200.01f, 0.0f, 0.25f, 262.144f), 1020 * kNsPerMs, d) == Fault::none);
  CHECK(d.increment.x == Approx(0.01f * std::cos(0.25f)).margin(2e-5));
  CHECK(v.faults()[Fault::out_of_range] == 2);
}
