// libFuzzer target: any frame through every decoder and the CAN receive path (WHEEL_TICKS pairing included);
// decoded values re-encode to the same values; the generic signal packer reads back what it wrote for any layout;
// the input as a candump line either is refused or formats back to a line that parses to the same frame. Built by
// scripts/fuzz.
#include <cstddef>
#include <cstdint>
#include <cstring>

#include "hal/can/can_input.hpp"
#include "hal/can/candump.hpp"
#include "hal/can/estimate_frames.hpp"
#include "hal/can/signal.hpp"
#include "hal/sensors/odometry/can.hpp"
#include "hal/sensors/range_scan/can_frames.hpp"
#include "hal/sensors/steering/can.hpp"
#include "hal/sensors/twist/can.hpp"
#include "hal/sensors/wheel_ticks/can.hpp"

using namespace hal::can;

namespace {

// What the bus can deliver, checked per sample.
struct NullPort final : hal::PortImplementation<NullPort, hal::SensorPort> {
  void handle(const hal::WheelTicks& s) {
    if (s.wheel_count > 7) __builtin_trap();  // WheelCount is 3 bits
    for (std::uint32_t c : s.count)
      if (c > 0xFFFF) __builtin_trap();
  }
  void handle(const hal::SteeringSample& s) {
    if (!__builtin_isfinite(s.angle_rad)) __builtin_trap();
  }
  void handle(const hal::TwistSample& s) {
    if (!__builtin_isfinite(s.v1_mps) || !__builtin_isfinite(s.v2_mps) || !__builtin_isfinite(s.w_rps)) __builtin_trap();
  }
  void handle(const hal::OdometrySample& s) {
    if (!s.pose.is_finite() || s.wrap_m != dbc::kOdometryWrapM) __builtin_trap();
    if (s.pose.x < 0.0f || !(s.pose.x < s.wrap_m) || s.pose.y < 0.0f || !(s.pose.y < s.wrap_m)) __builtin_trap();
    if (s.pose.theta > 3.1415927f || s.pose.theta < -3.1415927f) __builtin_trap();
  }
  void handle(const hal::RangeScanView& s) {
    for (std::size_t i = 0; i < s.count; ++i)
      if (s.ranges[i] != s.ranges[i]) __builtin_trap();  // the bus cannot produce NaN
  }
  void handle(const hal::LandmarkSightingView&) { __builtin_trap(); }  // CAN carries none
};

template <typename Msg>
void roundtrip(const CanFrame& f, bool (*same)(const Msg&, const Msg&)) {
  Msg a;
  if (decode(f, a) != CodecStatus::ok) return;
  CanFrame g;
  if (encode(a, g) != CodecStatus::ok) return;  // decoded raw values may lie outside the DBC range: allowed
  Msg b;
  if (decode(g, b) != CodecStatus::ok || !same(a, b)) __builtin_trap();
}

// Re-decoding may move a value by one raw step: a 32-bit raw value does not fit a float's 24-bit significand, and
// raw * factor / factor rounds twice. Anything more is a codec bug.
bool near(float a, float b, float step) {
  const float d = a > b ? a - b : b - a;
  const float scale = a > 0.0f ? a : -a;
  return d <= step * 1.0001f + scale * 2.4e-7f;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 11) return 0;
  static const std::uint32_t ids[] = {dbc::kWheelTicksId,    dbc::kSteeringId,      dbc::kWheelTicksExtId,
                                      dbc::kTwistId,         dbc::kOdometryId,      dbc::kScanHeaderId,
                                      dbc::kScanInfoId,      dbc::kScanDataId,      dbc::kPoseEstimateId,
                                      dbc::kPoseSigmaId,     dbc::kPoseCorrelationId, dbc::kEstimatorStatusId,
                                      0x7FF};
  constexpr std::size_t kIds = sizeof ids / sizeof ids[0];
  CanFrame f;
  f.id = ids[data[0] % kIds];
  f.dlc = static_cast<std::uint8_t>(data[1] % 10 == 9 ? 8 : data[1] % 9);
  std::memcpy(f.data, data + 2, 8);

  roundtrip<WheelTicksMsg>(f, [](const WheelTicksMsg& a, const WheelTicksMsg& b) {
    return a.ticks[0] == b.ticks[0] && a.ticks[1] == b.ticks[1] && a.wheel_count == b.wheel_count &&
           a.counter == b.counter;
  });
  roundtrip<WheelTicksExtMsg>(f, [](const WheelTicksExtMsg& a, const WheelTicksExtMsg& b) {
    return a.ticks[0] == b.ticks[0] && a.ticks[1] == b.ticks[1] && a.counter == b.counter;
  });
  roundtrip<TwistMsg>(f, [](const TwistMsg& a, const TwistMsg& b) {
    return near(a.v1_mps, b.v1_mps, 1e-3f) && near(a.v2_mps, b.v2_mps, 1e-3f) && near(a.w_rps, b.w_rps, 1e-3f) &&
           a.counter == b.counter;
  });
  roundtrip<OdometryMsg>(f, [](const OdometryMsg& a, const OdometryMsg& b) {
    return a.x_mm == b.x_mm && a.y_mm == b.y_mm && a.theta == b.theta && a.counter == b.counter;
  });
  roundtrip<SteeringMsg>(f, [](const SteeringMsg& a, const SteeringMsg& b) {
    return near(a.angle_rad, b.angle_rad, 1e-4f) && a.counter == b.counter;
  });
  roundtrip<ScanHeaderMsg>(f, [](const ScanHeaderMsg& a, const ScanHeaderMsg& b) {
    return a.scan_id == b.scan_id && a.range_count == b.range_count && a.scan_crc == b.scan_crc &&
           near(a.scan_time_s, b.scan_time_s, 1e-4f) && near(a.range_max_m, b.range_max_m, 1e-3f);
  });
  roundtrip<ScanInfoMsg>(f, [](const ScanInfoMsg& a, const ScanInfoMsg& b) {
    return a.scan_id == b.scan_id && near(a.range_min_m, b.range_min_m, 1e-3f) &&
           near(a.angle_min_rad, b.angle_min_rad, 1e-4f) && near(a.angle_increment_rad, b.angle_increment_rad, 1e-9f);
  });
  roundtrip<ScanDataMsg>(f, [](const ScanDataMsg& a, const ScanDataMsg& b) {
    return a.scan_id == b.scan_id && a.seq == b.seq && std::memcmp(a.range_mm, b.range_mm, sizeof a.range_mm) == 0;
  });
  roundtrip<PoseEstimateMsg>(f, [](const PoseEstimateMsg& a, const PoseEstimateMsg& b) {
    return near(a.x_m, b.x_m, 1e-3f) && near(a.y_m, b.y_m, 1e-3f) && near(a.theta_rad, b.theta_rad, 1e-4f) &&
           a.counter == b.counter;
  });
  roundtrip<PoseSigmaMsg>(f, [](const PoseSigmaMsg& a, const PoseSigmaMsg& b) {
    return near(a.sigma_x_m, b.sigma_x_m, 1e-3f) && near(a.sigma_y_m, b.sigma_y_m, 1e-3f) &&
           near(a.sigma_theta_rad, b.sigma_theta_rad, 1e-4f);
  });
  roundtrip<PoseCorrelationMsg>(f, [](const PoseCorrelationMsg& a, const PoseCorrelationMsg& b) {
    return near(a.xy, b.xy, 1e-4f) && near(a.xtheta, b.xtheta, 1e-4f) && near(a.ytheta, b.ytheta, 1e-4f);
  });
  roundtrip<EstimatorStatusMsg>(f, [](const EstimatorStatusMsg& a, const EstimatorStatusMsg& b) {
    return a.status_word == b.status_word && a.rejected_inputs == b.rejected_inputs && a.counter == b.counter;
  });

  static NullPort port;
  static ScanReassembler<32> scans;
  static CanInput input(scans, port);
  input.on_frame(f, static_cast<hal::TimeNs>(data[10]) * 1000);

  // The input as one line of a candump log: refused with a reason, or a frame that formats back to a line that
  // parses to the same frame and stamp.
  {
    CanFrame parsed;
    hal::TimeNs stamp = 0;
    const auto* text = reinterpret_cast<const char*>(data);
    if (parse_candump_line(text, size, parsed, stamp) == CandumpStatus::ok) {
      if (parsed.dlc > kMaxDlc || parsed.id > 0x7FFu || stamp < 0) __builtin_trap();
      char line[kCandumpLineMax];
      const std::size_t n = format_candump_line(parsed, stamp, "can0", line);
      if (n == 0 || n > kCandumpLineMax || line[n - 1] != '\n') __builtin_trap();
      CanFrame again;
      hal::TimeNs stamp2 = -1;
      if (parse_candump_line(line, n - 1, again, stamp2) != CandumpStatus::ok) __builtin_trap();
      if (again.id != parsed.id || again.dlc != parsed.dlc || std::memcmp(again.data, parsed.data, parsed.dlc) != 0 ||
          stamp2 != stamp)
        __builtin_trap();
    }
  }

  // Any signal layout: what insert_raw writes, extract_raw reads back, and no bit outside the signal changes.
  if (size >= 24) {
    SignalSpec s{"s", static_cast<std::uint16_t>(data[11] % 64), static_cast<std::uint8_t>(1 + data[12] % 32),
                 (data[13] & 1) ? ByteOrder::big_endian : ByteOrder::little_endian, (data[13] & 2) != 0, 1.0f, 0.0f,
                 0.0f, 1.0f, ""};
    std::uint64_t raw = 0;
    std::memcpy(&raw, data + 14, 8);
    raw &= (std::uint64_t{1} << s.length) - 1;
    std::uint8_t buf[8], before[8], cleared[8], cleared_before[8];
    std::memcpy(buf, data + 2, 8);
    std::memcpy(before, buf, 8);
    insert_raw(buf, s, raw);
    // A Motorola signal may run off the end of the frame: only the bits inside are written and read.
    std::memcpy(cleared, buf, 8);
    std::memcpy(cleared_before, before, 8);
    insert_raw(cleared, s, 0);
    insert_raw(cleared_before, s, 0);
    if (std::memcmp(cleared, cleared_before, 8) != 0) __builtin_trap();
    std::uint8_t probe[8] = {};
    insert_raw(probe, s, raw);
    if (extract_raw(probe, s) != extract_raw(buf, s)) __builtin_trap();
    const bool fits = s.order == ByteOrder::little_endian ? s.start_bit + s.length <= 64u : true;
    if (fits && s.order == ByteOrder::little_endian && extract_raw(buf, s) != raw) __builtin_trap();
  }
  return 0;
}
