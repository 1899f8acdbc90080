// The CAN receive path: frames to HAL samples, and every bad frame class rejected with its reason counted, up to
// the HAL gate (ValidatedInputs), so that a frame that decodes but carries a bad value is counted there.
#include <catch2/catch.hpp>
#include <vector>

#include "hal/can/can_input.hpp"
#include "hal/can/estimate_frames.hpp"
#include "hal/sensors/odometry/can.hpp"
#include "hal/sensors/range_scan/can_frames.hpp"
#include "hal/sensors/steering/can.hpp"
#include "hal/sensors/twist/can.hpp"
#include "hal/sensors/wheel_ticks/can.hpp"
#include "hal/validated_inputs.hpp"

using namespace hal::can;
using hal::kNsPerMs;

namespace {

struct Recorder final : hal::PortImplementation<Recorder, hal::SensorPort> {
  std::vector<hal::WheelTicks> wheels;
  std::vector<hal::SteeringSample> steering;
  std::vector<hal::TwistSample> twists;
  std::vector<hal::OdometrySample> odometry;
  std::vector<std::size_t> scans;
  int landmarks = 0;
  void handle(const hal::WheelTicks& s) { wheels.push_back(s); }
  void handle(const hal::SteeringSample& s) { steering.push_back(s); }
  void handle(const hal::TwistSample& s) { twists.push_back(s); }
  void handle(const hal::OdometrySample& s) { odometry.push_back(s); }
  void handle(const hal::RangeScanView& s) { scans.push_back(s.count); }
  void handle(const hal::LandmarkSightingView&) { ++landmarks; }
};

// Counts the checked samples that pass the gate.
struct CheckedCounter final : hal::PortImplementation<CheckedCounter, hal::ValidatedSensorPort> {
  int motion = 0, steering = 0, other = 0;
  void handle(const hal::WheelTickDelta&) { ++motion; }
  void handle(const hal::SteeringSample&) { ++steering; }
  template <typename Checked>
  void handle(const Checked&) {
    ++other;
  }
};

CanFrame wheel_frame(std::uint16_t l, std::uint16_t r, std::uint8_t counter, std::uint8_t wheel_count = 2) {
  CanFrame f;
  REQUIRE(encode(WheelTicksMsg{{l, r}, wheel_count, counter}, f) == CodecStatus::ok);
  return f;
}

CanFrame wheel_ext_frame(std::uint16_t t2, std::uint16_t t3, std::uint8_t counter) {
  CanFrame f;
  REQUIRE(encode(WheelTicksExtMsg{{t2, t3}, counter}, f) == CodecStatus::ok);
  return f;
}

CanFrame twist_frame(float v1, float v2, float w, std::uint8_t counter) {
  CanFrame f;
  REQUIRE(encode(TwistMsg{v1, v2, w, counter}, f) == CodecStatus::ok);
  return f;
}

CanFrame odometry_frame(const est::Pose2& pose, std::uint8_t counter) {
  hal::OdometrySample s;
  s.pose = pose;
  OdometryMsg m;
  REQUIRE(to_message(s, counter, m));
  CanFrame f;
  REQUIRE(encode(m, f) == CodecStatus::ok);
  return f;
}

CanFrame steering_frame(float a, std::uint8_t counter) {
  CanFrame f;
  REQUIRE(encode(SteeringMsg{a, counter}, f) == CodecStatus::ok);
  return f;
}

}  // namespace

TEST_CASE("wheel, steering and scan frames become HAL samples stamped with their receive time", "[can][input]") {
  Recorder port;
  ScanReassembler<64> scans;
  CanInput in(scans, port);
  in.on_frame(wheel_frame(100, 65535, 0), 1000);
  in.on_frame(steering_frame(-0.3f, 0), 2000);
  std::vector<float> ranges(20, 2.0f);
  std::vector<CanFrame> frames(scan_frame_count(20));
  hal::RangeScanView v{0, {-1.0f, 0.1f, 0.1f, 10.0f, 0.1f}, ranges.data(), ranges.size()};
  REQUIRE(split_scan(v, 0, frames.data(), frames.size()).status == CodecStatus::ok);
  for (const CanFrame& f : frames) in.on_frame(f, 3000);
  REQUIRE(port.wheels.size() == 1);
  CHECK(port.wheels[0].stamp_ns == 1000);
  CHECK(port.wheels[0].wheel_count == 2);
  CHECK(port.wheels[0].count[0] == 100);
  CHECK(port.wheels[0].count[1] == 65535);
  REQUIRE(port.steering.size() == 1);
  CHECK(port.steering[0].stamp_ns == 2000);
  CHECK(port.steering[0].angle_rad == Approx(-0.3).margin(1e-4));
  REQUIRE(port.scans.size() == 1);
  CHECK(port.scans[0] == 20);
  CHECK(in.rejects().total() == 0);
  CHECK(in.frames_accepted() == 2 + frames.size());
}

TEST_CASE("unknown id, wrong DLC, bad checksum and duplicates are rejected and counted", "[can][input]") {
  Recorder port;
  ScanReassembler<64> scans;
  CanInput in(scans, port);
  CanFrame unknown = wheel_frame(1, 2, 0);
  unknown.id = 0x7FF;
  in.on_frame(unknown, 0);
  CanFrame pose;
  REQUIRE(encode(PoseEstimateMsg{1, 2, 0, 0}, pose) == CodecStatus::ok);
  in.on_frame(pose, 0);  // our own output is not an input
  CanFrame short_frame = wheel_frame(1, 2, 0);
  short_frame.dlc = 4;
  in.on_frame(short_frame, 0);
  CanFrame corrupt = steering_frame(0.1f, 0);
  corrupt.data[1] ^= 0x10;
  in.on_frame(corrupt, 0);
  in.on_frame(wheel_frame(1, 2, 3), 10);
  in.on_frame(wheel_frame(1, 2, 3), 20);  // the same alive counter again: a duplicate
  CHECK(in.rejects()[FrameReject::unknown_id] == 2);
  CHECK(in.rejects()[FrameReject::wrong_dlc] == 1);
  CHECK(in.rejects()[FrameReject::bad_checksum] == 1);
  CHECK(in.rejects()[FrameReject::duplicate] == 1);
  CHECK(port.wheels.size() == 1);
  CHECK(port.steering.empty());
}

TEST_CASE("a skipped alive counter counts lost frames, wrapping at 16, and keeps the frame", "[can][input]") {
  Recorder port;
  ScanReassembler<64> scans;
  CanInput in(scans, port);
  for (int c : {14, 15, 0, 1, 4, 5}) in.on_frame(steering_frame(0.0f, static_cast<std::uint8_t>(c)), c * 10);
  CHECK(in.rejects()[FrameReject::counter_gap] == 1);
  CHECK(port.steering.size() == 6);
}

TEST_CASE("through the HAL gate: out-of-range steering, time going backwards and stale frames are counted",
          "[can][input]") {
  struct Clock final : hal::Clock {
    hal::TimeNs now = 0;
    hal::TimeNs now_ns() override { return now; }
  } clock;
  CheckedCounter sink;
  hal::InputLimits limits;
  limits.wheels.counter_bits = kCanWheelCounterBits;
  limits.steering.max_angle_rad = 0.6f;
  hal::ValidatedInputs gate(limits, clock, sink);
  ScanReassembler<64> scans;
  CanInput in(scans, gate);

  clock.now = 100 * kNsPerMs;
  in.on_frame(steering_frame(0.65f, 0), 100 * kNsPerMs);      // beyond the mechanical stop
  in.on_frame(steering_frame(0.2f, 1), 100 * kNsPerMs);
  in.on_frame(steering_frame(0.2f, 2), 95 * kNsPerMs);        // receive stamps going backwards
  in.on_frame(wheel_frame(65500, 0, 0), 100 * kNsPerMs);
  clock.now = 110 * kNsPerMs;
  in.on_frame(wheel_frame(100, 0, 1), 110 * kNsPerMs);        // +136 ticks through the wrap: fine
  clock.now = 500 * kNsPerMs;
  in.on_frame(wheel_frame(200, 0, 2), 120 * kNsPerMs);        // stale by the time it is read
  CHECK(gate.faults()[hal::Fault::out_of_range] == 1);
  CHECK(gate.faults()[hal::Fault::time_backwards] == 1);
  CHECK(gate.faults()[hal::Fault::stale] == 1);
  CHECK(sink.steering == 1);
  CHECK(sink.motion == 2);
}

TEST_CASE("twist and odometry frames become HAL samples; odometry carries its counters' period", "[can][input]") {
  Recorder port;
  ScanReassembler<64> scans;
  CanInput in(scans, port);
  in.on_frame(twist_frame(0.5f, -0.25f, 1.5f, 0), 1000);
  in.on_frame(odometry_frame({1.5f, -0.002f, 0.5f}, 0), 2000);
  REQUIRE(port.twists.size() == 1u);
  CHECK(port.twists[0].stamp_ns == 1000);
  CHECK(port.twists[0].v1_mps == Approx(0.5).margin(5e-4));
  CHECK(port.twists[0].v2_mps == Approx(-0.25).margin(5e-4));
  CHECK(port.twists[0].w_rps == Approx(1.5).margin(5e-4));
  REQUIRE(port.odometry.size() == 1u);
  CHECK(port.odometry[0].stamp_ns == 2000);
  CHECK(port.odometry[0].pose.x == Approx(1.5).margin(5e-4));
  CHECK(port.odometry[0].pose.y == Approx(262.142).margin(5e-4));  // -2 mm on a 2^18 mm counter
  CHECK(port.odometry[0].pose.theta == Approx(0.5).margin(1e-4));
  CHECK(port.odometry[0].wrap_m == dbc::kOdometryWrapM);
  CHECK(in.rejects().total() == 0u);
  CHECK(in.frames_accepted() == 2u);
  // Each has its own alive counter.
  in.on_frame(twist_frame(0.5f, 0.0f, 0.0f, 0), 3000);
  in.on_frame(odometry_frame({1.5f, 0.0f, 0.5f}, 2), 4000);
  CHECK(in.rejects()[FrameReject::duplicate] == 1u);
  CHECK(in.rejects()[FrameReject::counter_gap] == 1u);
  CHECK(port.twists.size() == 1u);
  CHECK(port.odometry.size() == 2u);
}

TEST_CASE("a four-wheel sample is WHEEL_TICKS then WHEEL_TICKS_EXT; a broken pair is counted as incomplete",
          "[can][input]") {
  Recorder port;
  ScanReassembler<64> scans;
  CanInput in(scans, port);
  in.on_frame(wheel_frame(1, 2, 0, 4), 1000);
  CHECK(port.wheels.empty());  // waits for its second frame
  in.on_frame(wheel_ext_frame(3, 4, 0), 1100);
  REQUIRE(port.wheels.size() == 1u);
  CHECK(port.wheels[0].stamp_ns == 1000);  // the first frame's receive time
  CHECK(port.wheels[0].wheel_count == 4);
  CHECK(port.wheels[0].count[0] == 1u);
  CHECK(port.wheels[0].count[3] == 4u);
  CHECK(in.rejects().total() == 0u);

  in.on_frame(wheel_frame(5, 6, 1, 3), 2000);
  in.on_frame(wheel_frame(7, 8, 2, 3), 2010);  // the extension of counter 1 never came
  in.on_frame(wheel_ext_frame(9, 0, 2), 2020);
  REQUIRE(port.wheels.size() == 2u);
  CHECK(port.wheels[1].count[0] == 7u);
  CHECK(port.wheels[1].count[2] == 9u);
  CHECK(in.rejects()[FrameReject::incomplete] == 1u);

  in.on_frame(wheel_frame(1, 1, 3, 4), 3000);
  in.on_frame(wheel_ext_frame(1, 1, 9), 3010);  // another sample's extension
  in.on_frame(wheel_ext_frame(1, 1, 3), 3020);  // too late: the first frame was dropped
  CHECK(port.wheels.size() == 2u);
  CHECK(in.rejects()[FrameReject::incomplete] == 3u);
  CHECK(in.rejects().total() == 3u);
  CHECK(port.landmarks == 0);  // CAN carries no landmark sightings
}
