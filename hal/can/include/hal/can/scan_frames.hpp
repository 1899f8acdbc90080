#pragma once
// A rangefinder scan on the bus: SCAN_HEADER, SCAN_INFO, then ceil(count / 3) SCAN_DATA frames (estimator.dbc).
#include <cstddef>
#include <cstdint>

#include "hal/can/frame.hpp"
#include "hal/can/messages.hpp"
#include "hal/range_scan.hpp"

namespace hal::can {

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
