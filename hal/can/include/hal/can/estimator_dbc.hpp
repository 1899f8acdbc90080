#pragma once
// The codec's copy of hal/can/estimator.dbc: every message and signal, as constant tables in flash.
// tests/test_can_dbc.cpp parses the DBC file and requires these tables to match it field for field.
//
// Classic CAN (8-byte frames), not CAN FD: the boards this firmware targets (Cortex-M4F parts with bxCAN-class
// controllers) have no FD, and every tool and logger reads classic frames. The price is bandwidth for scans: 3 beams
// per frame, so a 360-beam scan is 122 frames (~15 kbit, 30 % of a 500 kbit/s bus at 10 Hz) and a 1081-beam scan
// is 363 frames (~44 kbit: decimate it, or move the scan messages to CAN FD, where one 64-byte frame carries 30
// beams; the table-driven codec extends to that by its DLC).
#include <cstddef>
#include <cstdint>

namespace hal::can {

enum class ByteOrder : std::uint8_t { little_endian, big_endian };  // DBC @1 (Intel), @0 (Motorola)

struct SignalSpec {
  const char* name;
  std::uint16_t start_bit;  // DBC numbering: Intel = LSB position; Motorola = MSB position (bit 7 of byte 0 is 7)
  std::uint8_t length;
  ByteOrder order;
  bool is_signed;
  float factor;
  float offset;
  float minimum;
  float maximum;
  const char* unit;
};

struct MessageSpec {
  const char* name;
  std::uint32_t id;
  std::uint8_t dlc;
  const char* sender;
  const SignalSpec* signals;
  std::size_t signal_count;
};

namespace dbc {

inline constexpr auto LE = ByteOrder::little_endian;
inline constexpr auto BE = ByteOrder::big_endian;

// Signal indices per message follow the order of the tables below.
enum WheelTicksSignal : std::size_t { kTicksLeft, kTicksRight, kWheelCounter, kWheelChecksum };
inline constexpr SignalSpec kWheelTicksSignals[] = {
    {"TicksLeft", 0, 16, LE, false, 1.0f, 0.0f, 0.0f, 65535.0f, "tick"},
    {"TicksRight", 16, 16, LE, false, 1.0f, 0.0f, 0.0f, 65535.0f, "tick"},
    {"Counter", 48, 4, LE, false, 1.0f, 0.0f, 0.0f, 15.0f, ""},
    {"Checksum", 56, 8, LE, false, 1.0f, 0.0f, 0.0f, 255.0f, ""},
};

enum SteeringSignal : std::size_t { kSteeringAngle, kSteeringCounter, kSteeringChecksum };
inline constexpr SignalSpec kSteeringSignals[] = {
    {"SteeringAngle", 7, 16, BE, true, 0.0001f, 0.0f, -3.2768f, 3.2767f, "rad"},
    {"Counter", 51, 4, BE, false, 1.0f, 0.0f, 0.0f, 15.0f, ""},
    {"Checksum", 63, 8, BE, false, 1.0f, 0.0f, 0.0f, 255.0f, ""},
};

enum ScanHeaderSignal : std::size_t { kHeaderScanId, kRangeCount, kScanCrc, kScanTime, kRangeMax };
inline constexpr SignalSpec kScanHeaderSignals[] = {
    {"ScanId", 0, 4, LE, false, 1.0f, 0.0f, 0.0f, 15.0f, ""},
    {"RangeCount", 4, 12, LE, false, 1.0f, 0.0f, 0.0f, 4095.0f, ""},
    {"ScanCrc", 16, 16, LE, false, 1.0f, 0.0f, 0.0f, 65535.0f, ""},
    {"ScanTime", 32, 16, LE, false, 0.0001f, 0.0f, 0.0f, 6.5535f, "s"},
    {"RangeMax", 48, 16, LE, false, 0.001f, 0.0f, 0.0f, 65.535f, "m"},
};

enum ScanInfoSignal : std::size_t { kInfoScanId, kRangeMin, kAngleMin, kAngleIncrement };
inline constexpr SignalSpec kScanInfoSignals[] = {
    {"ScanId", 0, 4, LE, false, 1.0f, 0.0f, 0.0f, 15.0f, ""},
    {"RangeMin", 4, 12, LE, false, 0.001f, 0.0f, 0.0f, 4.095f, "m"},
    {"AngleMin", 16, 16, LE, true, 0.0001f, 0.0f, -3.2768f, 3.2767f, "rad"},
    {"AngleIncrement", 32, 32, LE, true, 1e-09f, 0.0f, -2.147483648f, 2.147483647f, "rad"},
};

enum ScanDataSignal : std::size_t { kDataScanId, kSeq, kRange0, kRange1, kRange2 };
inline constexpr SignalSpec kScanDataSignals[] = {
    {"ScanId", 0, 4, LE, false, 1.0f, 0.0f, 0.0f, 15.0f, ""},
    {"Seq", 4, 12, LE, false, 1.0f, 0.0f, 0.0f, 4095.0f, ""},
    {"Range0", 16, 16, LE, false, 0.001f, 0.0f, 0.0f, 65.535f, "m"},
    {"Range1", 32, 16, LE, false, 0.001f, 0.0f, 0.0f, 65.535f, "m"},
    {"Range2", 48, 16, LE, false, 0.001f, 0.0f, 0.0f, 65.535f, "m"},
};

enum PoseEstimateSignal : std::size_t { kX, kY, kTheta, kPoseCounter };
inline constexpr SignalSpec kPoseEstimateSignals[] = {
    {"X", 0, 22, LE, true, 0.001f, 0.0f, -2097.152f, 2097.151f, "m"},
    {"Y", 22, 22, LE, true, 0.001f, 0.0f, -2097.152f, 2097.151f, "m"},
    {"Theta", 44, 16, LE, true, 0.0001f, 0.0f, -3.2768f, 3.2767f, "rad"},
    {"Counter", 60, 4, LE, false, 1.0f, 0.0f, 0.0f, 15.0f, ""},
};

enum PoseSigmaSignal : std::size_t { kSigmaX, kSigmaY, kSigmaTheta, kSigmaCounter };
inline constexpr SignalSpec kPoseSigmaSignals[] = {
    {"SigmaX", 0, 16, LE, false, 0.001f, 0.0f, 0.0f, 65.535f, "m"},
    {"SigmaY", 16, 16, LE, false, 0.001f, 0.0f, 0.0f, 65.535f, "m"},
    {"SigmaTheta", 32, 16, LE, false, 0.0001f, 0.0f, 0.0f, 6.5535f, "rad"},
    {"Counter", 48, 4, LE, false, 1.0f, 0.0f, 0.0f, 15.0f, ""},
};

enum PoseCorrelationSignal : std::size_t { kCorrXY, kCorrXTheta, kCorrYTheta, kCorrCounter };
inline constexpr SignalSpec kPoseCorrelationSignals[] = {
    {"CorrXY", 0, 16, LE, true, 0.0001f, 0.0f, -1.0f, 1.0f, ""},
    {"CorrXTheta", 16, 16, LE, true, 0.0001f, 0.0f, -1.0f, 1.0f, ""},
    {"CorrYTheta", 32, 16, LE, true, 0.0001f, 0.0f, -1.0f, 1.0f, ""},
    {"Counter", 48, 4, LE, false, 1.0f, 0.0f, 0.0f, 15.0f, ""},
};

enum EstimatorStatusSignal : std::size_t { kStatusWord, kRejectedInputs, kStatusCounter };
inline constexpr SignalSpec kEstimatorStatusSignals[] = {
    {"StatusWord", 0, 32, LE, false, 1.0f, 0.0f, 0.0f, 4294967295.0f, ""},
    {"RejectedInputs", 32, 16, LE, false, 1.0f, 0.0f, 0.0f, 65535.0f, ""},
    {"Counter", 48, 4, LE, false, 1.0f, 0.0f, 0.0f, 15.0f, ""},
};

template <std::size_t N>
constexpr std::size_t count_of(const SignalSpec (&)[N]) {
  return N;
}

inline constexpr std::uint32_t kWheelTicksId = 0x100;
inline constexpr std::uint32_t kSteeringId = 0x101;
inline constexpr std::uint32_t kScanHeaderId = 0x110;
inline constexpr std::uint32_t kScanInfoId = 0x111;
inline constexpr std::uint32_t kScanDataId = 0x112;
inline constexpr std::uint32_t kPoseEstimateId = 0x300;
inline constexpr std::uint32_t kPoseSigmaId = 0x301;
inline constexpr std::uint32_t kPoseCorrelationId = 0x302;
inline constexpr std::uint32_t kEstimatorStatusId = 0x310;

inline constexpr MessageSpec kMessages[] = {
    {"WHEEL_TICKS", kWheelTicksId, 8, "WHEEL_ENCODERS", kWheelTicksSignals, count_of(kWheelTicksSignals)},
    {"STEERING", kSteeringId, 8, "STEERING_SENSOR", kSteeringSignals, count_of(kSteeringSignals)},
    {"SCAN_HEADER", kScanHeaderId, 8, "RANGEFINDER", kScanHeaderSignals, count_of(kScanHeaderSignals)},
    {"SCAN_INFO", kScanInfoId, 8, "RANGEFINDER", kScanInfoSignals, count_of(kScanInfoSignals)},
    {"SCAN_DATA", kScanDataId, 8, "RANGEFINDER", kScanDataSignals, count_of(kScanDataSignals)},
    {"POSE_ESTIMATE", kPoseEstimateId, 8, "ESTIMATOR", kPoseEstimateSignals, count_of(kPoseEstimateSignals)},
    {"POSE_SIGMA", kPoseSigmaId, 8, "ESTIMATOR", kPoseSigmaSignals, count_of(kPoseSigmaSignals)},
    {"POSE_CORRELATION", kPoseCorrelationId, 8, "ESTIMATOR", kPoseCorrelationSignals,
     count_of(kPoseCorrelationSignals)},
    {"ESTIMATOR_STATUS", kEstimatorStatusId, 8, "ESTIMATOR", kEstimatorStatusSignals,
     count_of(kEstimatorStatusSignals)},
};

// The ids the estimator receives (its kernel receive filter) and sends.
inline constexpr std::uint32_t kInputIds[] = {kWheelTicksId, kSteeringId, kScanHeaderId, kScanInfoId, kScanDataId};
inline constexpr std::uint32_t kOutputIds[] = {kPoseEstimateId, kPoseSigmaId, kPoseCorrelationId,
                                               kEstimatorStatusId};

}  // namespace dbc

// The message with this id, or nullptr.
const MessageSpec* find_message(std::uint32_t id);

}  // namespace hal::can
