#pragma once
// Every message of estimator.dbc as a struct in SI units, with encode (struct -> frame) and decode (frame ->
// struct). Encoding fills id, dlc, the alive counter given and the checksum; decoding checks id, dlc and checksum.
#include <cstdint>

#include "hal/can/estimator_dbc.hpp"
#include "hal/can/frame.hpp"

namespace hal::can {

enum class CodecStatus : std::uint8_t {
  ok,
  wrong_id,      // the frame is another message
  wrong_dlc,     // not the DBC's length
  bad_checksum,  // per-frame CRC-8 mismatch
  not_finite,    // encode: NaN or infinity in a signal that has no code for it
  out_of_range,  // encode: outside the signal's DBC range
};

const char* to_string(CodecStatus s);

struct WheelTicksMsg {
  std::uint16_t ticks_left = 0;  // raw hardware counters (wrap at 65536)
  std::uint16_t ticks_right = 0;
  std::uint8_t counter = 0;      // alive counter, 0..15
};

struct SteeringMsg {
  float angle_rad = 0.0f;
  std::uint8_t counter = 0;
};

struct ScanHeaderMsg {
  std::uint8_t scan_id = 0;       // 0..15
  std::uint16_t range_count = 0;  // 0..4095
  std::uint16_t scan_crc = 0;
  float scan_time_s = 0.0f;
  float range_max_m = 0.0f;
};

struct ScanInfoMsg {
  std::uint8_t scan_id = 0;
  float range_min_m = 0.0f;
  float angle_min_rad = 0.0f;
  float angle_increment_rad = 0.0f;
};

inline constexpr std::uint16_t kRangesPerDataFrame = 3;
inline constexpr std::uint16_t kNoReturnRaw = 0xFFFF;

struct ScanDataMsg {
  std::uint8_t scan_id = 0;
  std::uint16_t seq = 0;                            // 0..4095
  std::uint16_t range_mm[kRangesPerDataFrame] = {};  // raw millimetres; kNoReturnRaw = no return
};

// A range in metres as the bus carries it: +inf and anything at or above 65.535 m are "no return"; NaN and
// negative readings (no valid measurement) become 0, which every sensor's range_min rejects.
std::uint16_t range_to_raw_mm(float range_m);
// No return decodes as +inf (ROS REP 117), which the HAL classifies as a max-range reading.
float range_from_raw_mm(std::uint16_t raw);

struct PoseEstimateMsg {
  float x_m = 0.0f;
  float y_m = 0.0f;
  float theta_rad = 0.0f;
  std::uint8_t counter = 0;
};

struct PoseSigmaMsg {
  float sigma_x_m = 0.0f;
  float sigma_y_m = 0.0f;
  float sigma_theta_rad = 0.0f;
  std::uint8_t counter = 0;
};

struct PoseCorrelationMsg {
  float xy = 0.0f;
  float xtheta = 0.0f;
  float ytheta = 0.0f;
  std::uint8_t counter = 0;
};

struct EstimatorStatusMsg {
  std::uint32_t status_word = 0;
  std::uint16_t rejected_inputs = 0;
  std::uint8_t counter = 0;
};

CodecStatus encode(const WheelTicksMsg& m, CanFrame& f);
CodecStatus encode(const SteeringMsg& m, CanFrame& f);
CodecStatus encode(const ScanHeaderMsg& m, CanFrame& f);
CodecStatus encode(const ScanInfoMsg& m, CanFrame& f);
CodecStatus encode(const ScanDataMsg& m, CanFrame& f);
CodecStatus encode(const PoseEstimateMsg& m, CanFrame& f);
CodecStatus encode(const PoseSigmaMsg& m, CanFrame& f);
CodecStatus encode(const PoseCorrelationMsg& m, CanFrame& f);
CodecStatus encode(const EstimatorStatusMsg& m, CanFrame& f);

CodecStatus decode(const CanFrame& f, WheelTicksMsg& m);
CodecStatus decode(const CanFrame& f, SteeringMsg& m);
CodecStatus decode(const CanFrame& f, ScanHeaderMsg& m);
CodecStatus decode(const CanFrame& f, ScanInfoMsg& m);
CodecStatus decode(const CanFrame& f, ScanDataMsg& m);
CodecStatus decode(const CanFrame& f, PoseEstimateMsg& m);
CodecStatus decode(const CanFrame& f, PoseSigmaMsg& m);
CodecStatus decode(const CanFrame& f, PoseCorrelationMsg& m);
CodecStatus decode(const CanFrame& f, EstimatorStatusMsg& m);

}  // namespace hal::can
