// The sender's side of the bus (hal/can/sample_frames.hpp): each raw sample as the frames its sensor puts on the
// bus, with each message's own alive counter; what does not fit is not sent (and uses no counter); and what a
// receiver (hal::can::CanInput) makes of the frames is the sample again, to the bus's resolution.
#include <catch2/catch.hpp>

#include <cmath>
#include <vector>

#include "hal/can/can_input.hpp"
#include "hal/can/estimator_dbc.hpp"
#include "hal/can/sample_frames.hpp"

using namespace hal::can;

namespace {

struct Received final : hal::PortImplementation<Received, hal::SensorPort> {
  std::vector<hal::WheelTicks> wheels;
  std::vector<hal::SteeringSample> steering;
  std::vector<hal::TwistSample> twists;
  std::vector<hal::OdometrySample> odometry;
  std::vector<std::vector<float>> scans;
  void handle(const hal::WheelTicks& s) { wheels.push_back(s); }
  void handle(const hal::SteeringSample& s) { steering.push_back(s); }
  void handle(const hal::TwistSample& s) { twists.push_back(s); }
  void handle(const hal::OdometrySample& s) { odometry.push_back(s); }
  void handle(const hal::RangeScanView& s) { scans.emplace_back(s.ranges, s.ranges + s.count); }
  void handle(const hal::LandmarkSightingView&) {}
};

hal::WheelTicks wheels(hal::TimeNs t, std::uint8_t n) {
  hal::WheelTicks s;
  s.stamp_ns = t;
  s.wheel_count = n;
  for (std::uint8_t i = 0; i < n && i < hal::kMaxWheels; ++i) s.count[i] = 1000u * (i + 1u);
  return s;
}

std::uint8_t counter_of(const CanFrame& f) {
  const MessageSpec* m = find_message(f.id);
  REQUIRE(m != nullptr);
  for (std::size_t i = 0; i < m->signal_count; ++i)
    if (std::string(m->signals[i].name) == "Counter") return static_cast<std::uint8_t>(extract_raw(f.data, m->signals[i]));
  FAIL("no Counter in " << m->name);
  return 0;
}

}  // namespace

TEST_CASE("each sample is the frames of its message: one, two for three or four wheels, a scan's many",
          "[sample_frames]") {
  SampleFrames enc;
  CanFrame out[130];
  REQUIRE(enc.encode(wheels(0, 2), out, 130) == 1u);
  CHECK(out[0].id == dbc::kWheelTicksId);
  REQUIRE(enc.encode(wheels(0, 4), out, 130) == 2u);
  CHECK(out[0].id == dbc::kWheelTicksId);
  CHECK(out[1].id == dbc::kWheelTicksExtId);
  REQUIRE(enc.encode(hal::SteeringSample{0, 0.1f}, out, 130) == 1u);
  CHECK(out[0].id == dbc::kSteeringId);
  REQUIRE(enc.encode(hal::TwistSample{0, 0.5f, 0.0f, 0.1f}, out, 130) == 1u);
  CHECK(out[0].id == dbc::kTwistId);
  hal::OdometrySample o;
  o.pose = {1.0f, -2.0f, 0.5f};
  REQUIRE(enc.encode(o, out, 130) == 1u);
  CHECK(out[0].id == dbc::kOdometryId);
  std::vector<float> r(360, 2.0f);
  REQUIRE(enc.encode(hal::RangeScanView{0, {-3.14f, 0.0174f, 0.1f, 12.0f, 0.1f}, r.data(), r.size()}, out, 130) ==
          scan_frame_count(360));
  CHECK(out[0].id == dbc::kScanHeaderId);
  CHECK(out[1].id == dbc::kScanInfoId);
  CHECK(out[121].id == dbc::kScanDataId);
  const hal::LandmarkFeature f[1] = {};
  CHECK(enc.encode(hal::LandmarkSightingView{0, f, 1}, out, 130) == 0u);  // sightings travel on LCM
}

TEST_CASE("each message keeps its own alive counter, +1 mod 16, shared by a WHEEL_TICKS pair", "[sample_frames]") {
  SampleFrames enc;
  CanFrame out[2];
  for (int k = 0; k < 20; ++k) {
    REQUIRE(enc.encode(wheels(k, 3), out, 2) == 2u);
    CHECK(counter_of(out[0]) == k % 16);
    CHECK(counter_of(out[1]) == k % 16);
    if (k % 2 == 0) {  // the twist's counter does not move with the wheels'
      REQUIRE(enc.encode(hal::TwistSample{k, 0.1f, 0.0f, 0.0f}, out, 2) == 1u);
      CHECK(counter_of(out[0]) == (k / 2) % 16);
    }
  }
  REQUIRE(enc.encode(hal::SteeringSample{0, 0.0f}, out, 2) == 1u);
  CHECK(counter_of(out[0]) == 0);
  hal::OdometrySample o;
  REQUIRE(enc.encode(o, out, 2) == 1u);
  CHECK(counter_of(out[0]) == 0);
  REQUIRE(enc.encode(o, out, 2) == 1u);
  CHECK(counter_of(out[0]) == 1);
}

TEST_CASE("a sample that does not fit the bus, or the room given, is not sent and uses no counter",
          "[sample_frames]") {
  SampleFrames enc;
  CanFrame out[4];
  CHECK(enc.encode(hal::TwistSample{0, 40.0f, 0.0f, 0.0f}, out, 4) == 0u);  // beyond +-32.767 m/s
  CHECK(enc.encode(hal::TwistSample{0, std::nanf(""), 0.0f, 0.0f}, out, 4) == 0u);
  REQUIRE(enc.encode(hal::TwistSample{0, 1.0f, 0.0f, 0.0f}, out, 4) == 1u);
  CHECK(counter_of(out[0]) == 0);  // the refused ones did not count
  CHECK(enc.encode(hal::SteeringSample{0, 4.0f}, out, 4) == 0u);
  hal::OdometrySample nan_pose;
  nan_pose.pose.x = std::nanf("");
  CHECK(enc.encode(nan_pose, out, 4) == 0u);
  CHECK(enc.encode(wheels(0, 0), out, 4) == 0u);
  CHECK(enc.encode(wheels(0, 5), out, 4) == 0u);
  CHECK(enc.encode(wheels(0, 4), out, 1) == 0u);  // two frames, room for one
  CHECK(enc.encode(hal::SteeringSample{0, 0.1f}, out, 0) == 0u);
  std::vector<float> r(30, 1.0f);
  CHECK(enc.encode(hal::RangeScanView{0, {0.0f, 0.01f, 0.1f, 10.0f, 0.1f}, r.data(), r.size()}, out, 4) == 0u);
  REQUIRE(enc.encode(wheels(0, 4), out, 4) == 2u);
  CHECK(counter_of(out[0]) == 0);
}

TEST_CASE("a receiver makes the samples again from the frames, to the bus's resolution", "[sample_frames]") {
  SampleFrames enc;
  Received port;
  ScanReassembler<400> scans;
  CanInput in(scans, port);
  std::vector<CanFrame> out(scan_frame_count(360));
  auto send = [&](const auto& s, hal::TimeNs t) {
    const std::size_t n = enc.encode(s, out.data(), out.size());
    REQUIRE(n > 0u);
    for (std::size_t i = 0; i < n; ++i) in.on_frame(out[i], t);
  };
  hal::WheelTicks w = wheels(0, 4);
  w.count[3] = 70000;  // a 32-bit counter: the bus carries its low 16 bits
  send(w, 1000);
  send(hal::SteeringSample{0, -0.25f}, 2000);
  send(hal::TwistSample{0, 1.2345f, -0.5f, 0.75f}, 3000);
  hal::OdometrySample o;
  o.pose = {-1.5f, 300.0f, -2.0f};
  send(o, 4000);
  std::vector<float> r(360);
  for (std::size_t i = 0; i < r.size(); ++i) r[i] = 0.5f + 0.01f * static_cast<float>(i);
  send(hal::RangeScanView{0, {-3.14f, 0.0174f, 0.1f, 12.0f, 0.1f}, r.data(), r.size()}, 5000);
  CHECK(in.rejects().total() == 0u);
  REQUIRE(port.wheels.size() == 1u);
  CHECK(port.wheels[0].stamp_ns == 1000);  // the receive time, as on a bus
  CHECK(port.wheels[0].wheel_count == 4);
  CHECK(port.wheels[0].count[1] == 2000u);
  CHECK(port.wheels[0].count[3] == (70000u & 0xFFFFu));
  REQUIRE(port.steering.size() == 1u);
  CHECK(port.steering[0].angle_rad == Approx(-0.25).margin(5e-5));
  REQUIRE(port.twists.size() == 1u);
  CHECK(port.twists[0].v1_mps == Approx(1.2345).margin(6e-4));  // half a step and the float rounding
  CHECK(port.twists[0].w_rps == Approx(0.75).margin(5e-4));
  REQUIRE(port.odometry.size() == 1u);
  // Wrapped into the counters' periods: the same pose modulo 262.144 m and one turn.
  CHECK(port.odometry[0].pose.x == Approx(262.144 - 1.5).margin(1e-3));
  CHECK(port.odometry[0].pose.y == Approx(300.0 - 262.144).margin(1e-3));
  CHECK(port.odometry[0].pose.theta == Approx(-2.0).margin(1e-4));
  REQUIRE(port.scans.size() == 1u);
  REQUIRE(port.scans[0].size() == 360u);
  for (std::size_t i = 0; i < r.size(); i += 37) CHECK(port.scans[0][i] == Approx(r[i]).margin(5e-4));
}
