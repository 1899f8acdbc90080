// CAN codec: frames as estimator.dbc lays them out (hand-computed bytes), round trips of every message, and
// rejection of wrong ids, wrong DLC, bad checksums, NaN and out-of-range values.
#include <catch2/catch.hpp>
#include <cstring>
#include <limits>

#include "hal/can/crc.hpp"
#include "hal/can/messages.hpp"
#include "hal/can/signal.hpp"

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

TEST_CASE("WHEEL_TICKS bytes: little-endian counters, alive counter in byte 6, CRC-8 in byte 7", "[can][codec]") {
  CanFrame f;
  REQUIRE(encode(WheelTicksMsg{0x1234, 0xABCD, 5}, f) == CodecStatus::ok);
  CHECK(f.id == 0x100);
  CHECK(f.dlc == 8);
  const std::uint8_t expect[7] = {0x34, 0x12, 0xCD, 0xAB, 0x00, 0x00, 0x05};
  CHECK(std::memcmp(f.data, expect, 7) == 0);
  CHECK(f.data[7] == crc8_of(0x100, expect));
  WheelTicksMsg m;
  REQUIRE(decode(f, m) == CodecStatus::ok);
  CHECK(m.ticks_left == 0x1234);
  CHECK(m.ticks_right == 0xABCD);
  CHECK(m.counter == 5);
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
  REQUIRE(encode(WheelTicksMsg{1, 2, 3}, f) == CodecStatus::ok);
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
