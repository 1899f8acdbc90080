// CAN codec: frames as estimator.dbc lays them out (hand-computed bytes), round trips of every message, and
// rejection of wrong ids, wrong DLC, bad checksums, NaN and out-of-range values; WHEEL_TICKS paired with its
// WHEEL_TICKS_EXT, and ODOMETRY's wrapping counters.
#include <catch2/catch.hpp>
#include <cstring>
#include <limits>

#include "hal/can/crc.hpp"
#include "hal/can/estimate_frames.hpp"
#include "hal/can/signal.hpp"
#include "hal/sensors/odometry/can.hpp"
#include "hal/sensors/range_scan/can_frames.hpp"
#include "hal/sensors/steering/can.hpp"
#include "hal/sensors/twist/can.hpp"
#include "hal/sensors/wheel_ticks/can.hpp"

using namespace hal::can;

namespace {

std::uint64_t le64(const CanFrame& f) {
  std::uint64_t v = 0;
  for (int i = 7; i >= 0; --i) v = (v << 8) | f.data[i];
  return v;
}

std::uint8_t crc8_of(std::uint32_t id, const std::uint8_t* d) {
  Crc8J1850 c;
  c.add(static_cast<std::uint8_t>(id & 0xFF));
  c.add(static_cast<std::uint8_t>(id >> 8));
  c.add(d, 7);
  return c.value();
}

// Half a scaling step plus float rounding of raw * factor.
double tol(const SignalSpec& s, double value) { return 0.5 * static_cast<double>(s.factor) + 1e-6 * (1.0 + std::abs(value)); }

}  // namespace

TEST_CASE("checksums match their published check values", "[can][crc]") {
  const std::uint8_t check[] = {'1', '2', '3', '4', '5', '6', '7', '8', '9'};
  Crc8J1850 c8;
  c8.add(check, sizeof check);
  CHECK(c8.value() == 0x4B);
  Crc16Ccitt c16;
  c16.add(check, sizeof check);
  CHECK(c16.value() == 0x29B1);
}

TEST_CASE("WHEEL_TICKS bytes: little-endian counters, wheel count in byte 4, alive counter in byte 6, CRC-8 in byte 7",
          "[can][codec]") {
  CanFrame f;
  REQUIRE(encode(WheelTicksMsg{{0x1234, 0xABCD}, 2, 5}, f) == CodecStatus::ok);
  CHECK(f.id == 0x100);
  CHECK(f.dlc == 8);
  const std::uint8_t expect[7] = {0x34, 0x12, 0xCD, 0xAB, 0x02, 0x00, 0x05};
  CHECK(std::memcmp(f.data, expect, 7) == 0);
  CHECK(f.data[7] == crc8_of(0x100, expect));
  WheelTicksMsg m;
  REQUIRE(decode(f, m) == CodecStatus::ok);
  CHECK(m.ticks[0] == 0x1234);
  CHECK(m.ticks[1] == 0xABCD);
  CHECK(m.wheel_count == 2);
  CHECK(m.counter == 5);
}

TEST_CASE("WHEEL_TICKS_EXT bytes: wheels 2 and 3 little-endian, the first frame's counter in byte 6", "[can][codec]") {
  CanFrame f;
  REQUIRE(encode(WheelTicksExtMsg{{0xBEEF, 0x0102}, 9}, f) == CodecStatus::ok);
  CHECK(f.id == 0x102);
  CHECK(f.dlc == 8);
  const std::uint8_t expect[7] = {0xEF, 0xBE, 0x02, 0x01, 0x00, 0x00, 0x09};
  CHECK(std::memcmp(f.data, expect, 7) == 0);
  CHECK(f.data[7] == crc8_of(0x102, expect));
  WheelTicksExtMsg m;
  REQUIRE(decode(f, m) == CodecStatus::ok);
  CHECK(m.ticks[0] == 0xBEEF);
  CHECK(m.ticks[1] == 0x0102);
  CHECK(m.counter == 9);
  WheelTicksMsg not_first;
  CHECK(decode(f, not_first) == CodecStatus::wrong_id);
}

TEST_CASE("TWIST bytes: signed 16-bit mm/s and mrad/s, round trip within half a step", "[can][codec]") {
  using namespace dbc;
  CanFrame f;
  REQUIRE(encode(TwistMsg{1.5f, -0.25f, 0.001f, 7}, f) == CodecStatus::ok);
  CHECK(f.id == 0x103);
  const std::uint64_t v2_raw = 0x10000u - 250u;
  const std::uint64_t low = 1500u | (v2_raw << 16) | (std::uint64_t{1} << 32) | (std::uint64_t{7} << 48);
  CHECK((le64(f) & 0x00FFFFFFFFFFFFFFull) == low);
  CHECK(f.data[7] == crc8_of(0x103, f.data));
  for (float v : {-32.768f, -1.0f, 0.0f, 0.0004f, 3.14159f, 32.767f}) {
    TwistMsg a{v, -0.5f * v, 0.25f * v, 3}, b;
    REQUIRE(encode(a, f) == CodecStatus::ok);
    REQUIRE(decode(f, b) == CodecStatus::ok);
    CHECK(b.v1_mps == Approx(v).margin(tol(kTwistSignals[kTwistV1], v)));
    CHECK(b.v2_mps == Approx(-0.5f * v).margin(tol(kTwistSignals[kTwistV2], v)));
    CHECK(b.w_rps == Approx(0.25f * v).margin(tol(kTwistSignals[kTwistW], v)));
    CHECK(b.counter == 3);
  }
  const hal::TwistSample s = to_sample(TwistMsg{0.5f, 0.25f, -1.0f, 2}, 1234);
  CHECK(s.stamp_ns == 1234);
  CHECK(s.v1_mps == 0.5f);
  CHECK(s.v2_mps == 0.25f);
  CHECK(s.w_rps == -1.0f);
  const TwistMsg back = to_message(s, 11);
  CHECK(back.v1_mps == 0.5f);
  CHECK(back.counter == 11);
}

TEST_CASE("TWIST encode refuses NaN, infinity and speeds beyond +-32.767", "[can][codec]") {
  CanFrame f;
  const float nan = std::numeric_limits<float>::quiet_NaN();
  CHECK(encode(TwistMsg{nan, 0.0f, 0.0f, 0}, f) == CodecStatus::not_finite);
  CHECK(encode(TwistMsg{0.0f, std::numeric_limits<float>::infinity(), 0.0f, 0}, f) == CodecStatus::not_finite);
  CHECK(encode(TwistMsg{0.0f, 0.0f, nan, 0}, f) == CodecStatus::not_finite);
  CHECK(encode(TwistMsg{32.8f, 0.0f, 0.0f, 0}, f) == CodecStatus::out_of_range);
  CHECK(encode(TwistMsg{0.0f, -32.8f, 0.0f, 0}, f) == CodecStatus::out_of_range);
  CHECK(encode(TwistMsg{0.0f, 0.0f, 40.0f, 0}, f) == CodecStatus::out_of_range);
}

TEST_CASE("ODOMETRY bytes: 18-bit x and y, 16-bit theta, counter beside the checksum", "[can][codec]") {
  CanFrame f;
  OdometryMsg m;
  m.x_mm = 0x3FFFF;
  m.y_mm = 0x12345;
  m.theta = 0xABCD;
  m.counter = 0xE;
  REQUIRE(encode(m, f) == CodecStatus::ok);
  CHECK(f.id == 0x104);
  const std::uint64_t low = 0x3FFFFull | (0x12345ull << 18) | (0xABCDull << 36) | (0xEull << 52);
  CHECK((le64(f) & 0x00FFFFFFFFFFFFFFull) == low);
  CHECK(f.data[7] == crc8_of(0x104, f.data));
  OdometryMsg b;
  REQUIRE(decode(f, b) == CodecStatus::ok);
  CHECK(b.x_mm == 0x3FFFFu);
  CHECK(b.y_mm == 0x12345u);
  CHECK(b.theta == 0xABCD);
  CHECK(b.counter == 0xE);
  // x and y are counters modulo 2^18: a value past the period goes on the bus reduced.
  m.x_mm = 0x40000u + 5u;
  REQUIRE(encode(m, f) == CodecStatus::ok);
  REQUIRE(decode(f, b) == CodecStatus::ok);
  CHECK(b.x_mm == 5u);
}

TEST_CASE("an odometry pose becomes wrapping counters: negative and large positions, any heading", "[can][codec]") {
  using namespace dbc;
  OdometryMsg m;
  hal::OdometrySample s;
  s.pose = {1.234f, -0.001f, -0.5f * est::kPi};
  REQUIRE(to_message(s, 4, m));
  CHECK(m.x_mm == 1234u);
  CHECK(m.y_mm == 262143u);  // -1 mm modulo 2^18
  CHECK(m.theta == 49152);   // -a quarter turn is three quarters
  CHECK(m.counter == 4);
  s.pose = {262.144f + 0.5f, 1000.0f, 7.0f * est::kPi};
  REQUIRE(to_message(s, 0, m));
  CHECK(m.x_mm == 500u);
  CHECK(m.y_mm == 1000000u % 262144u);
  CHECK(m.theta == 32768);  // 3.5 turns: half a turn
  s.pose.x = std::numeric_limits<float>::quiet_NaN();
  CHECK_FALSE(to_message(s, 0, m));
  s.pose = {1.0f, 2.0f, std::numeric_limits<float>::infinity()};
  CHECK_FALSE(to_message(s, 0, m));

  // Back: metres in [0, 262.144), theta in (-pi, pi], and the period the validator differences with.
  m.x_mm = 262143u;
  m.y_mm = 5u;
  m.theta = 49152;
  const hal::OdometrySample back = to_sample(m, 777);
  CHECK(back.stamp_ns == 777);
  CHECK(back.pose.x == Approx(262.143).margin(1e-4));
  CHECK(back.pose.y == Approx(0.005).margin(1e-7));
  CHECK(back.pose.theta == Approx(-0.5 * M_PI).margin(1e-4));
  CHECK(back.wrap_m == kOdometryWrapM);
  CHECK(kOdometryWrapM == 262.144f);
  CHECK(static_cast<double>(kOdometryThetaStep) == Approx(2.0 * M_PI / 65536.0).epsilon(1e-7));
}

TEST_CASE("one or two wheels are one WHEEL_TICKS frame; three or four add WHEEL_TICKS_EXT with the same counter",
          "[can][codec]") {
  hal::WheelTicks s;
  s.stamp_ns = 1;
  s.count[0] = 70000;  // beyond 16 bits: the bus carries the low 16 (the receiver's counter is 16 bits wide)
  s.count[1] = 2;
  s.count[2] = 3;
  s.count[3] = 65535;
  CanFrame out[2];
  for (std::uint8_t n : {std::uint8_t{1}, std::uint8_t{2}}) {
    s.wheel_count = n;
    REQUIRE(encode_wheel_ticks(s, 9, out) == 1u);
    WheelTicksMsg m;
    REQUIRE(decode(out[0], m) == CodecStatus::ok);
    CHECK(m.wheel_count == n);
    CHECK(m.ticks[0] == (70000u & 0xFFFFu));
    CHECK(m.counter == 9);
  }
  for (std::uint8_t n : {std::uint8_t{3}, std::uint8_t{4}}) {
    s.wheel_count = n;
    REQUIRE(encode_wheel_ticks(s, 12, out) == 2u);
    WheelTicksMsg m;
    WheelTicksExtMsg e;
    REQUIRE(decode(out[0], m) == CodecStatus::ok);
    REQUIRE(decode(out[1], e) == CodecStatus::ok);
    CHECK(m.wheel_count == n);
    CHECK(e.ticks[0] == 3);
    CHECK(e.ticks[1] == 65535);
    CHECK(e.counter == 12);
    CHECK(m.counter == 12);
  }
  s.wheel_count = 0;
  CHECK(encode_wheel_ticks(s, 0, out) == 0u);
  s.wheel_count = 5;
  CHECK(encode_wheel_ticks(s, 0, out) == 0u);
  // A frame's own WheelCount must be what the DBC allows, 1 to 4.
  CHECK(encode(WheelTicksMsg{{1, 2}, 0, 0}, out[0]) == CodecStatus::out_of_range);
  CHECK(encode(WheelTicksMsg{{1, 2}, 5, 0}, out[0]) == CodecStatus::out_of_range);
  CHECK(encode(WheelTicksMsg{{1, 2}, 4, 0}, out[0]) == CodecStatus::ok);
}

TEST_CASE("WHEEL_TICKS pairs with its WHEEL_TICKS_EXT by the alive counter; a broken pair is incomplete",
          "[can][codec]") {
  WheelTicksFrames pairs;
  hal::WheelTicks out;
  // Two wheels: the first frame is the sample, at its stamp.
  WheelTicksFrames::Result r = pairs.on_first(WheelTicksMsg{{10, 20}, 2, 0}, 100, out);
  CHECK(r.sample);
  CHECK_FALSE(r.incomplete);
  CHECK(out.stamp_ns == 100);
  CHECK(out.wheel_count == 2);
  CHECK(out.count[1] == 20);
  // Four wheels: the first frame waits, the second with the same counter completes it (stamped with the first's).
  r = pairs.on_first(WheelTicksMsg{{1, 2}, 4, 5}, 200, out);
  CHECK_FALSE(r.sample);
  CHECK_FALSE(r.incomplete);
  r = pairs.on_second(WheelTicksExtMsg{{3, 4}, 5}, out);
  REQUIRE(r.sample);
  CHECK_FALSE(r.incomplete);
  CHECK(out.stamp_ns == 200);
  CHECK(out.wheel_count == 4);
  CHECK(out.count[0] == 1);
  CHECK(out.count[1] == 2);
  CHECK(out.count[2] == 3);
  CHECK(out.count[3] == 4);
  // A second frame of another counter: the waiting first frame and it are dropped.
  pairs.on_first(WheelTicksMsg{{1, 2}, 3, 6}, 300, out);
  r = pairs.on_second(WheelTicksExtMsg{{3, 0}, 7}, out);
  CHECK_FALSE(r.sample);
  CHECK(r.incomplete);
  // ... and nothing is waiting any more: even the right counter now has no first frame.
  r = pairs.on_second(WheelTicksExtMsg{{3, 0}, 6}, out);
  CHECK_FALSE(r.sample);
  CHECK(r.incomplete);
  // A first frame not completed before the next WHEEL_TICKS is dropped; the new one waits in its place.
  pairs.on_first(WheelTicksMsg{{1, 2}, 3, 8}, 400, out);
  r = pairs.on_first(WheelTicksMsg{{5, 6}, 3, 9}, 410, out);
  CHECK(r.incomplete);
  CHECK_FALSE(r.sample);
  r = pairs.on_second(WheelTicksExtMsg{{7, 0}, 9}, out);
  REQUIRE(r.sample);
  CHECK(out.stamp_ns == 410);
  CHECK(out.wheel_count == 3);
  CHECK(out.count[0] == 5);
  CHECK(out.count[2] == 7);
  // A two-wheel frame arriving while a four-wheel one waits: the waiting one is incomplete, the new one passes.
  pairs.on_first(WheelTicksMsg{{1, 2}, 4, 10}, 500, out);
  r = pairs.on_first(WheelTicksMsg{{8, 9}, 2, 11}, 510, out);
  CHECK(r.incomplete);
  CHECK(r.sample);
  CHECK(out.count[0] == 8);
}

TEST_CASE("STEERING bytes: Motorola signed angle in bytes 0-1", "[can][codec]") {
  CanFrame f;
  REQUIRE(encode(SteeringMsg{0.1234f, 3}, f) == CodecStatus::ok);
  CHECK(f.id == 0x101);
  CHECK(f.data[0] == 0x04);  // 1234 = 0x04D2, most significant byte first
  CHECK(f.data[1] == 0xD2);
  CHECK(f.data[6] == 0x03);
  CHECK(f.data[7] == crc8_of(0x101, f.data));
  REQUIRE(encode(SteeringMsg{-0.1234f, 15}, f) == CodecStatus::ok);
  CHECK(f.data[0] == 0xFB);  // -1234 = 0xFB2E
  CHECK(f.data[1] == 0x2E);
  SteeringMsg m;
  REQUIRE(decode(f, m) == CodecStatus::ok);
  CHECK(m.angle_rad == Approx(-0.1234).margin(1e-7));
  CHECK(m.counter == 15);
}

TEST_CASE("POSE_ESTIMATE bytes: 22-bit signed x and y, 16-bit theta, counter in the top nibble", "[can][codec]") {
  CanFrame f;
  REQUIRE(encode(PoseEstimateMsg{1.5f, -2.0f, 0.5f, 9}, f) == CodecStatus::ok);
  const std::uint64_t y_raw = (std::uint64_t{1} << 22) - 2000u;  // two's complement in 22 bits
  const std::uint64_t expect = 1500u | (y_raw << 22) | (std::uint64_t{5000} << 44) | (std::uint64_t{9} << 60);
  CHECK(le64(f) == expect);
}

TEST_CASE("SCAN_INFO bytes: 12-bit range_min beside a 4-bit scan id, 1e-9 rad angle increment", "[can][codec]") {
  CanFrame f;
  REQUIRE(encode(ScanInfoMsg{7, 0.02f, -2.3562f, 0.004363323f}, f) == CodecStatus::ok);
  const std::uint64_t angle_min_raw = (std::uint64_t{1} << 16) - 23562u;
  const std::uint64_t expect = 7u | (std::uint64_t{20} << 4) | (angle_min_raw << 16) | (std::uint64_t{4363323} << 32);
  CHECK(le64(f) == expect);
}

TEST_CASE("every message survives encode then decode within half a scaling step", "[can][codec]") {
  using namespace dbc;
  CanFrame f;
  {
    ScanHeaderMsg a{11, 1081, 0xBEEF, 0.025f, 30.0f}, b;
    REQUIRE(encode(a, f) == CodecStatus::ok);
    REQUIRE(decode(f, b) == CodecStatus::ok);
    CHECK(b.scan_id == 11);
    CHECK(b.range_count == 1081);
    CHECK(b.scan_crc == 0xBEEF);
    CHECK(b.scan_time_s == Approx(0.025).margin(tol(kScanHeaderSignals[kScanTime], 0.025)));
    CHECK(b.range_max_m == Approx(30.0).margin(tol(kScanHeaderSignals[kRangeMax], 30.0)));
  }
  {
    ScanInfoMsg a{15, 4.095f, 3.2767f, -0.0123456f}, b;
    REQUIRE(encode(a, f) == CodecStatus::ok);
    REQUIRE(decode(f, b) == CodecStatus::ok);
    CHECK(b.scan_id == 15);
    CHECK(b.range_min_m == Approx(4.095).margin(tol(kScanInfoSignals[kRangeMin], 4.095)));
    CHECK(b.angle_min_rad == Approx(3.2767).margin(tol(kScanInfoSignals[kAngleMin], 3.2767)));
    CHECK(b.angle_increment_rad == Approx(-0.0123456).margin(1e-9));
  }
  {
    ScanDataMsg a{3, 4095, {0, 12345, kNoReturnRaw}}, b;
    REQUIRE(encode(a, f) == CodecStatus::ok);
    REQUIRE(decode(f, b) == CodecStatus::ok);
    CHECK(b.scan_id == 3);
    CHECK(b.seq == 4095);
    CHECK(b.range_mm[1] == 12345);
    CHECK(b.range_mm[2] == kNoReturnRaw);
  }
  for (float x : {-2097.152f, -1.0f, 0.0f, 0.001f, 2097.151f}) {
    PoseEstimateMsg a{x, -0.5f * x, 3.1415926f, 4}, b;
    REQUIRE(encode(a, f) == CodecStatus::ok);
    REQUIRE(decode(f, b) == CodecStatus::ok);
    CHECK(b.x_m == Approx(x).margin(tol(kPoseEstimateSignals[kX], x)));
    CHECK(b.y_m == Approx(-0.5f * x).margin(tol(kPoseEstimateSignals[kY], x)));
    CHECK(b.theta_rad == Approx(3.1415926).margin(tol(kPoseEstimateSignals[kTheta], 3.15)));
    CHECK(b.counter == 4);
  }
  {
    PoseSigmaMsg a{0.123f, 65.535f, 0.0f, 15}, b;
    REQUIRE(encode(a, f) == CodecStatus::ok);
    REQUIRE(decode(f, b) == CodecStatus::ok);
    CHECK(b.sigma_x_m == Approx(0.123).margin(tol(kPoseSigmaSignals[kSigmaX], 0.123)));
    CHECK(b.sigma_y_m == Approx(65.535).margin(tol(kPoseSigmaSignals[kSigmaY], 65.535)));
    CHECK(b.sigma_theta_rad == 0.0f);
  }
  {
    PoseCorrelationMsg a{-1.0f, 0.5f, 1.0f, 0}, b;
    REQUIRE(encode(a, f) == CodecStatus::ok);
    REQUIRE(decode(f, b) == CodecStatus::ok);
    CHECK(b.xy == Approx(-1.0).margin(1e-6));
    CHECK(b.xtheta == Approx(0.5).margin(1e-6));
    CHECK(b.ytheta == Approx(1.0).margin(1e-6));
  }
  {
    EstimatorStatusMsg a{0xDEADBEEF, 65535, 12}, b;
    REQUIRE(encode(a, f) == CodecStatus::ok);
    REQUIRE(decode(f, b) == CodecStatus::ok);
    CHECK(b.status_word == 0xDEADBEEF);
    CHECK(b.rejected_inputs == 65535);
    CHECK(b.counter == 12);
  }
}

TEST_CASE("decode rejects another message's id and a wrong DLC", "[can][codec]") {
  CanFrame f;
  REQUIRE(encode(WheelTicksMsg{{1, 2}, 2, 3}, f) == CodecStatus::ok);
  SteeringMsg s;
  CHECK(decode(f, s) == CodecStatus::wrong_id);
  for (int dlc : {0, 1, 7}) {
    CanFrame g = f;
    g.dlc = static_cast<std::uint8_t>(dlc);
    WheelTicksMsg m;
    CHECK(decode(g, m) == CodecStatus::wrong_dlc);
    PoseEstimateMsg p;
    g.id = dbc::kPoseEstimateId;
    CHECK(decode(g, p) == CodecStatus::wrong_dlc);
  }
}

TEST_CASE("a flipped bit anywhere in a checksummed frame is a bad checksum", "[can][codec]") {
  CanFrame good;
  REQUIRE(encode(SteeringMsg{0.25f, 7}, good) == CodecStatus::ok);
  for (int bit = 0; bit < 64; ++bit) {
    CanFrame f = good;
    f.data[bit / 8] = static_cast<std::uint8_t>(f.data[bit / 8] ^ (1u << (bit % 8)));
    SteeringMsg m;
    CHECK(decode(f, m) == CodecStatus::bad_checksum);
  }
  // The id is part of the checksum: the same payload under WHEEL_TICKS' id is rejected.
  CanFrame moved = good;
  moved.id = dbc::kWheelTicksId;
  WheelTicksMsg w;
  CHECK(decode(moved, w) == CodecStatus::bad_checksum);
}

TEST_CASE("a flipped bit in WHEEL_TICKS, WHEEL_TICKS_EXT, TWIST or ODOMETRY is a bad checksum", "[can][codec]") {
  CanFrame frames[4];
  REQUIRE(encode(WheelTicksMsg{{100, 200}, 4, 3}, frames[0]) == CodecStatus::ok);
  REQUIRE(encode(WheelTicksExtMsg{{300, 400}, 3}, frames[1]) == CodecStatus::ok);
  REQUIRE(encode(TwistMsg{0.5f, -0.1f, 0.2f, 3}, frames[2]) == CodecStatus::ok);
  OdometryMsg o;
  o.x_mm = 1000;
  o.y_mm = 2000;
  o.theta = 300;
  REQUIRE(encode(o, frames[3]) == CodecStatus::ok);
  auto status = [](const CanFrame& f) {
    switch (f.id) {
      case dbc::kWheelTicksId: { WheelTicksMsg m; return decode(f, m); }
      case dbc::kWheelTicksExtId: { WheelTicksExtMsg m; return decode(f, m); }
      case dbc::kTwistId: { TwistMsg m; return decode(f, m); }
      default: { OdometryMsg m; return decode(f, m); }
    }
  };
  for (const CanFrame& good : frames) {
    INFO("id " << good.id);
    CHECK(status(good) == CodecStatus::ok);
    for (int bit = 0; bit < 64; ++bit) {
      CanFrame f = good;
      f.data[bit / 8] = static_cast<std::uint8_t>(f.data[bit / 8] ^ (1u << (bit % 8)));
      CHECK(status(f) == CodecStatus::bad_checksum);
    }
    CanFrame short_frame = good;
    short_frame.dlc = 7;
    CHECK(status(short_frame) == CodecStatus::wrong_dlc);
  }
}

TEST_CASE("encode rejects NaN, infinity and values outside the DBC range", "[can][codec]") {
  CanFrame f;
  const float nan = std::numeric_limits<float>::quiet_NaN();
  CHECK(encode(SteeringMsg{nan, 0}, f) == CodecStatus::not_finite);
  CHECK(encode(PoseEstimateMsg{std::numeric_limits<float>::infinity(), 0, 0, 0}, f) == CodecStatus::not_finite);
  CHECK(encode(SteeringMsg{3.3f, 0}, f) == CodecStatus::out_of_range);
  CHECK(encode(PoseEstimateMsg{2097.2f, 0, 0, 0}, f) == CodecStatus::out_of_range);
  CHECK(encode(PoseSigmaMsg{-0.01f, 0, 0, 0}, f) == CodecStatus::out_of_range);
  CHECK(encode(PoseCorrelationMsg{1.01f, 0, 0, 0}, f) == CodecStatus::out_of_range);
  CHECK(encode(ScanHeaderMsg{0, 4096, 0, 0.1f, 10.0f}, f) == CodecStatus::out_of_range);  // 12-bit count
  CHECK(encode(ScanInfoMsg{0, 4.2f, 0.0f, 0.01f}, f) == CodecStatus::out_of_range);
}

TEST_CASE("ranges on the bus: millimetres, no return as 0xFFFF and +inf", "[can][codec]") {
  CHECK(range_to_raw_mm(1.2345f) == 1235);  // round half away from zero: 1234.5 -> 1235
  CHECK(range_to_raw_mm(0.0f) == 0);
  CHECK(range_to_raw_mm(65.534f) == 65534);
  CHECK(range_to_raw_mm(65.535f) == kNoReturnRaw);
  CHECK(range_to_raw_mm(std::numeric_limits<float>::infinity()) == kNoReturnRaw);
  CHECK(range_to_raw_mm(std::numeric_limits<float>::quiet_NaN()) == 0);
  CHECK(range_to_raw_mm(-1.0f) == 0);
  CHECK(range_from_raw_mm(kNoReturnRaw) == std::numeric_limits<float>::infinity());
  CHECK(range_from_raw_mm(1500) == Approx(1.5).margin(1e-6));
}

TEST_CASE("Motorola and Intel packing agree with a bit-by-bit reference on every start bit", "[can][signal]") {
  // Reference: Motorola signals walk from the MSB at start_bit down, wrapping to bit 7 of the next byte.
  for (std::uint16_t start = 0; start < 64; ++start) {
    for (unsigned len : {1u, 5u, 12u, 16u}) {
      SignalSpec be{"s", start, static_cast<std::uint8_t>(len), ByteOrder::big_endian, false, 1.0f, 0.0f, 0.0f, 1.0f, ""};
      std::uint8_t data[8] = {};
      const std::uint64_t value = (std::uint64_t{0xA5A5} >> (16 - len)) | 1u;
      insert_raw(data, be, value);
      std::uint64_t ref = 0;
      unsigned pos = start;
      std::size_t taken = 0;
      for (; taken < len && pos < 64; ++taken) {
        ref = (ref << 1) | ((static_cast<unsigned>(data[pos / 8]) >> (pos % 8)) & 1u);
        pos = (pos % 8 == 0) ? pos + 15 : pos - 1;
      }
      if (taken == len) {
        CHECK(ref == (value & ((std::uint64_t{1} << len) - 1)));
        CHECK(extract_raw(data, be) == (value & ((std::uint64_t{1} << len) - 1)));
      }
    }
  }
}
