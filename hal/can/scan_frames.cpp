// Splitting a scan into frames (hal/can/scan_frames.hpp).
#include "hal/can/scan_frames.hpp"

#include "hal/can/crc.hpp"

namespace hal::can {

ScanSplit split_scan(const RangeScanView& scan, std::uint8_t scan_id, CanFrame* out, std::size_t max_frames) {
  ScanSplit result;
  if (scan.count == 0 || scan.count > kMaxScanRanges || scan.ranges == nullptr ||
      max_frames < scan_frame_count(scan.count)) {
    result.status = CodecStatus::out_of_range;
    return result;
  }
  const auto id = static_cast<std::uint8_t>(scan_id & 0x0Fu);

  ScanInfoMsg info;
  info.scan_id = id;
  info.range_min_m = scan.geometry.range_min_m;
  info.angle_min_rad = scan.geometry.angle_min_rad;
  info.angle_increment_rad = scan.geometry.angle_increment_rad;
  result.status = encode(info, out[1]);
  if (result.status != CodecStatus::ok) return result;

  Crc16Ccitt crc;
  crc.add(out[1].data, 8);
  const std::size_t data_frames = scan_data_frames(scan.count);
  for (std::size_t k = 0; k < data_frames; ++k) {
    ScanDataMsg data;
    data.scan_id = id;
    data.seq = static_cast<std::uint16_t>(k);
    for (std::size_t j = 0; j < kRangesPerDataFrame; ++j) {
      const std::size_t i = k * kRangesPerDataFrame + j;
      data.range_mm[j] = i < scan.count ? range_to_raw_mm(scan.ranges[i]) : 0;
    }
    result.status = encode(data, out[2 + k]);
    if (result.status != CodecStatus::ok) return result;
    crc.add(out[2 + k].data, 8);
  }

  ScanHeaderMsg header;
  header.scan_id = id;
  header.range_count = static_cast<std::uint16_t>(scan.count);
  header.scan_crc = crc.value();
  header.scan_time_s = scan.geometry.scan_time_s;
  header.range_max_m = scan.geometry.range_max_m;
  result.status = encode(header, out[0]);
  if (result.status != CodecStatus::ok) return result;
  result.frames = 2 + data_frames;
  return result;
}

}  // namespace hal::can
