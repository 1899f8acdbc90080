// The HAL's generic gate (hal/validated_inputs.hpp): every raw sample reaches its own sensor's validator, configured
// by its part of InputLimits, and what passes goes on as that sensor's checked sample; every reject is counted under
// its sensor, in the order of hal/samples.hpp.
#include <catch2/catch.hpp>

#include <cmath>
#include <functional>
#include <string>
#include <type_traits>
#include <vector>

#include "hal/validated_inputs.hpp"

using hal::Fault;
using hal::kNsPerMs;
using hal::TimeNs;

namespace {

struct FakeClock final : hal::Clock {
  TimeNs now = 0;
  TimeNs now_ns() override { return now; }
};

// What passed, by checked sample type.
struct Passed final : hal::PortImplementation<Passed, hal::ValidatedSensorPort> {
  std::vector<hal::WheelTickDelta> wheels;
  std::vector<hal::SteeringSample> steering;
  std::vector<hal::TwistSample> twists;
  std::vector<hal::OdometryDelta> odometry;
  std::vector<hal::RangeScanView> scans;
  std::vector<hal::LandmarkSightingView> sightings;
  void handle(const hal::WheelTickDelta& d) { wheels.push_back(d); }
  void handle(const hal::SteeringSample& s) { steering.push_back(s); }
  void handle(const hal::TwistSample& s) { twists.push_back(s); }
  void handle(const hal::OdometryDelta& d) { odometry.push_back(d); }
  void handle(const hal::RangeScanView& s) { scans.push_back(s); }
  void handle(const hal::LandmarkSightingView& s) { sightings.push_back(s); }
  std::size_t total() const {
    return wheels.size() + steering.size() + twists.size() + odometry.size() + scans.size() + sightings.size();
  }
};

hal::WheelTicks ticks(TimeNs t, std::uint32_t a, std::uint32_t b) {
  hal::WheelTicks s;
  s.stamp_ns = t;
  s.wheel_count = 2;
  s.count[0] = a;
  s.count[1] = b;
  return s;
}

hal::OdometrySample odom(TimeNs t, float x) {
  hal::OdometrySample s;
  s.stamp_ns = t;
  s.pose = {x, 0.0f, 0.0f};
  return s;
}

const float kRanges[4] = {1.0f, 2.0f, 3.0f, 4.0f};
const hal::LandmarkFeature kFeatures[1] = {{3.0f, 0.1f, 1.0f, 0}};

// The faults of each sensor, by name.
std::vector<std::pair<std::string, std::uint32_t>> faults_by_sensor(const hal::ValidatedInputs& in) {
  std::vector<std::pair<std::string, std::uint32_t>> out;
  in.for_each_sensor([&](const char* name, const hal::FaultCounters& f) { out.emplace_back(name, f.total()); });
  return out;
}

}  // namespace

static_assert(std::is_same_v<hal::Validation<hal::WheelTicks>::Checked, hal::WheelTickDelta>);
static_assert(std::is_same_v<hal::Validation<hal::OdometrySample>::Checked, hal::OdometryDelta>);
static_assert(std::is_same_v<hal::Validation<hal::TwistSample>::Validator, hal::TwistValidator>);
static_assert(hal::KindOfChecked<hal::OdometryDelta>::value == est::loop::InputKind::odometry);
static_assert(hal::KindOfChecked<hal::TwistSample>::value == est::loop::InputKind::twist);
static_assert(hal::KindOfChecked<hal::LandmarkSightingView>::value == est::loop::InputKind::landmark);

TEST_CASE("each raw sample reaches its own validator: a bad one is counted under its sensor only", "[gate]") {
  FakeClock clock;
  Passed out;
  hal::InputLimits limits;
  limits.scan.min_valid_beams = 1;
  hal::ValidatedInputs in(limits, clock, out);
  clock.now = 100 * kNsPerMs;
  const float nan = std::nanf("");
  struct Step {
    const char* sensor;
    std::function<void()> send;
  };
  hal::WheelTicks three = ticks(100 * kNsPerMs, 1, 1);
  three.wheel_count = 3;
  const float bad_ranges[4] = {nan, nan, nan, nan};
  const hal::LandmarkFeature bad_feature[1] = {{nan, 0.0f, 0.0f, 0}};
  const Step steps[] = {
      {"wheel_ticks", [&] { in.on(three); }},
      {"steering", [&] { in.on(hal::SteeringSample{100 * kNsPerMs, nan}); }},
      {"twist", [&] { in.on(hal::TwistSample{100 * kNsPerMs, 0.0f, nan, 0.0f}); }},
      {"odometry", [&] { in.on(odom(100 * kNsPerMs, nan)); }},
      {"scan", [&] { in.on(hal::RangeScanView{100 * kNsPerMs, {0.0f, 0.1f, 0.1f, 10.0f, 0.1f}, bad_ranges, 4}); }},
      {"landmarks", [&] { in.on(hal::LandmarkSightingView{100 * kNsPerMs, bad_feature, 1}); }},
  };
  for (std::size_t k = 0; k < std::size(steps); ++k) {
    INFO(steps[k].sensor);
    steps[k].send();
    const auto by_sensor = faults_by_sensor(in);
    REQUIRE(by_sensor.size() == std::size(steps));
    for (std::size_t j = 0; j < by_sensor.size(); ++j) {
      CHECK(by_sensor[j].first == steps[j].sensor);  // the order of hal/samples.hpp
      CHECK(by_sensor[j].second == (j <= k ? 1u : 0u));
    }
  }
  CHECK(out.total() == 0u);
  CHECK(in.faults().total() == 6u);
  CHECK(in.faults()[Fault::not_finite] == 4u);  // steering, twist, odometry, the landmark's feature
  CHECK(in.faults()[Fault::out_of_range] == 1u);  // three wheels for two
  CHECK(in.faults()[Fault::too_few_valid_beams] == 1u);
}

TEST_CASE("what passes goes on as its sensor's checked sample", "[gate]") {
  FakeClock clock;
  Passed out;
  hal::InputLimits limits;
  limits.scan.min_valid_beams = 1;
  hal::ValidatedInputs in(limits, clock, out);
  clock.now = 100 * kNsPerMs;
  in.on(ticks(90 * kNsPerMs, 10, 20));
  in.on(ticks(100 * kNsPerMs, 15, 18));
  in.on(hal::SteeringSample{100 * kNsPerMs, 0.2f});
  in.on(hal::TwistSample{100 * kNsPerMs, 0.5f, -0.1f, 0.3f});
  in.on(odom(90 * kNsPerMs, 1.0f));
  in.on(odom(100 * kNsPerMs, 1.02f));
  in.on(hal::RangeScanView{100 * kNsPerMs, {0.0f, 0.1f, 0.1f, 10.0f, 0.1f}, kRanges, 4});
  in.on(hal::LandmarkSightingView{100 * kNsPerMs, kFeatures, 1});
  CHECK(in.faults().total() == 0u);
  REQUIRE(out.wheels.size() == 2u);
  CHECK(out.wheels[1].ticks[0] == 5);  // unwrapped increments, not counters
  CHECK(out.wheels[1].ticks[1] == -2);
  CHECK(out.wheels[1].dt_ns == 10 * kNsPerMs);
  REQUIRE(out.steering.size() == 1u);
  CHECK(out.steering[0].angle_rad == 0.2f);
  REQUIRE(out.twists.size() == 1u);
  CHECK(out.twists[0].w_rps == 0.3f);
  REQUIRE(out.odometry.size() == 2u);
  CHECK(out.odometry[1].increment.x == Approx(0.02f));  // an increment, not a pose
  CHECK(out.odometry[1].source.pose.x == 1.02f);
  REQUIRE(out.scans.size() == 1u);
  CHECK(out.scans[0].count == 4u);
  REQUIRE(out.sightings.size() == 1u);
  CHECK(out.sightings[0].count == 1u);
}

TEST_CASE("each validator is configured by its part of InputLimits; set_timing sets every sensor's", "[gate]") {
  FakeClock clock;
  Passed out;
  hal::InputLimits limits;
  limits.twist.max_speed_mps = 1.0f;
  limits.odometry.max_speed_mps = 0.5f;
  limits.steering.max_angle_rad = 0.3f;
  limits.wheels.wheel_count = 3;
  limits.set_timing({50 * kNsPerMs, 1 * kNsPerMs});
  CHECK(limits.landmarks.timing.max_age_ns == 50 * kNsPerMs);
  CHECK(limits.odometry.timing.max_future_ns == 1 * kNsPerMs);
  hal::ValidatedInputs in(limits, clock, out);
  clock.now = 100 * kNsPerMs;
  in.on(hal::TwistSample{100 * kNsPerMs, 1.5f, 0.0f, 0.0f});  // within the default 5 m/s, beyond this base's 1
  in.on(hal::SteeringSample{100 * kNsPerMs, 0.4f});            // beyond 0.3
  in.on(ticks(100 * kNsPerMs, 1, 1));                          // two wheels on a three-wheel base
  in.on(odom(90 * kNsPerMs, 0.0f));
  in.on(odom(100 * kNsPerMs, 0.01f));                          // 1 m/s
  in.on(hal::TwistSample{40 * kNsPerMs, 0.5f, 0.0f, 0.0f});   // 60 ms old: stale at 50
  in.on(hal::TwistSample{102 * kNsPerMs, 0.5f, 0.0f, 0.0f});  // 2 ms ahead: from the future at 1
  CHECK(in.twist().faults()[Fault::out_of_range] == 1u);
  CHECK(in.twist().faults()[Fault::stale] == 1u);
  CHECK(in.twist().faults()[Fault::from_future] == 1u);
  CHECK(in.steering().faults()[Fault::out_of_range] == 1u);
  CHECK(in.wheels().faults()[Fault::out_of_range] == 1u);
  CHECK(in.odometry().faults()[Fault::out_of_range] == 1u);
  CHECK(in.faults().total() == 6u);
  CHECK(in.wheels().limits().wheel_count == 3u);
}

TEST_CASE("validator<Raw>() is the sensor's own validator; set_output moves where checked samples go", "[gate]") {
  FakeClock clock;
  Passed a, b;
  hal::ValidatedInputs in(hal::InputLimits{}, clock, a);
  CHECK(&in.validator<hal::WheelTicks>() == &in.wheels());
  CHECK(&in.validator<hal::SteeringSample>() == &in.steering());
  CHECK(&in.validator<hal::TwistSample>() == &in.twist());
  CHECK(&in.validator<hal::OdometrySample>() == &in.odometry());
  CHECK(&in.validator<hal::RangeScanView>() == &in.scan());
  CHECK(&in.validator<hal::LandmarkSightingView>() == &in.landmarks());
  CHECK(std::string(hal::TwistValidator::kName) == "twist");
  CHECK(std::string(hal::OdometryValidator::kName) == "odometry");
  in.on(hal::TwistSample{0, 0.1f, 0.0f, 0.0f});
  in.set_output(b);
  in.on(hal::TwistSample{1, 0.1f, 0.0f, 0.0f});
  CHECK(a.twists.size() == 1u);
  CHECK(b.twists.size() == 1u);
  CHECK(b.twists[0].stamp_ns == 1);
}
