#pragma once
// A rangefinder scan on the bus (estimator.dbc): SCAN_HEADER, SCAN_INFO, then ceil(count / 3) SCAN_DATA frames.
// The receiver's side is hal/sensors/range_scan/can_reassembler.hpp.
//
// Classic CAN (8-byte frames), not CAN FD: the boards this firmware targets (Cortex-M4F parts with bxCAN-class
// controllers) have no FD, and every tool and logger reads classic frames. The price is bandwidth for scans: 3 beams
// per frame, so a 360-beam scan is 122 frames (~15 kbit, 30 % of a 500 kbit/s bus at 10 Hz) and a 1081-beam scan
// is 363 frames (~44 kbit: decimate it, or move the scan messages to CAN FD, where one 64-byte frame carries 30
// beams; the table-driven codec extends to that by its DLC).
#include <cstddef>
#include <cstdint>

#include "hal/can/codec.hpp"
#include "hal/sensors/range_scan/range_scan.hpp"

namespace hal::can {

namespace dbc {
inline constexpr std::uint32_t kScanHeaderId = 0x110;
inline constexpr std::uint32_t kScanInfoId = 0x111;
inline constexpr std::uint32_t kScanDataId = 0x112;

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
}  // namespace dbc

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

CodecStatus encode(const ScanHeaderMsg& m, CanFrame& f);
CodecStatus encode(const ScanInfoMsg& m, CanFrame& f);
CodecStatus encode(const ScanDataMsg& m, CanFrame& f);
CodecStatus decode(const CanFrame& f, ScanHeaderMsg& m);
CodecStatus decode(const CanFrame& f, ScanInfoMsg& m);
CodecStatus decode(const CanFrame& f, ScanDataMsg& m);

// A range in metres as the bus carries it: +inf and anything at or above 65.535 m are "no return"; NaN and
// negative readings (no valid measurement) become 0, which every sensor's range_min rejects.
std::uint16_t range_to_raw_mm(float range_m);
// No return decodes as +inf (ROS REP 117), which the HAL classifies as a max-range reading.
float range_from_raw_mm(std::uint16_t raw);

inline constexpr std::size_t kMaxScanRanges = 4095;  // RangeCount is 12 bits

constexpr std::size_t scan_data_frames(std::size_t ranges) {
  return (ranges + kRangesPerDataFrame - 1u) / kRangesPerDataFrame;
}
constexpr std::size_t scan_frame_count(std::size_t ranges) { return 2u + scan_data_frames(ranges); }

struct ScanSplit {
  CodecStatus status = CodecStatus::ok;
  std::size_t frames = 0;  // written to out (0 unless status is ok)
};

// The sender's side (a rangefinder, the simulator, tests). Needs scan_frame_count(scan.count) frames of room,
// else out_of_range; the geometry must fit the DBC's ranges.
ScanSplit split_scan(const RangeScanView& scan, std::uint8_t scan_id, CanFrame* out, std::size_t max_frames);

}  // namespace hal::can
