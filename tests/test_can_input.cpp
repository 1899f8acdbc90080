// The CAN receive path: frames to HAL samples, and every bad frame class rejected with its reason counted, up to
// the HAL gate (ValidatedInputs), so that a frame that decodes but carries a bad value is counted there.
#include <catch2/catch.hpp>
#include <vector>

#include "hal/can/can_input.hpp"
#include "hal/can/messages.hpp"
#include "hal/can/scan_frames.hpp"
#include "hal/validated_inputs.hpp"

using namespace hal::can;
using hal::kNsPerMs;

namespace {

struct Recorder final : hal::SensorPort {
  std::vector<hal::WheelTicks> wheels;
  std::vector<hal::SteeringSample> steering;
  std::vector<std::size_t> scans;
  void on_wheel_ticks(const hal::WheelTicks& s) override { wheels.push_back(s); }
  void on_steering(const hal::SteeringSample& s) override { steering.push_back(s); }
  void on_range_scan(const hal::RangeScanView& s) override { scans.push_back(s.count); }
  void on_landmarks(const hal::LandmarkSightingView&) override {}
};

CanFrame wheel_frame(std::uint16_t l, std::uint16_t r, std::uint8_t counter) {
  CanFrame f;
  REQUIRE(encode(WheelTicksMsg{l, r, counter}, f) == CodecStatus::ok);
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
  struct Sink final : hal::ValidatedSensorPort {
    int motion = 0, steering = 0;
    void on_wheel_motion(const hal::WheelTickDelta&) override { ++motion; }
    void on_steering(const hal::SteeringSample&) override { ++steering; }
    void on_range_scan(const hal::RangeScanView&) override {}
    void on_landmarks(const hal::LandmarkSightingView&) override {}
  } sink;
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
