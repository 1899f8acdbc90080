// Scan frames and splitting a scan into them (hal/sensors/range_scan/can_frames.hpp).
#include "hal/sensors/range_scan/can_frames.hpp"

#include "hal/can/crc.hpp"

namespace hal::can {

using namespace dbc;

std::uint16_t range_to_raw_mm(float range_m) {
  if (range_m != range_m || range_m < 0.0f) return 0;
  if (range_m >= 65.535f) return kNoReturnRaw;
  return static_cast<std::uint16_t>(static_cast<std::uint32_t>(range_m * 1000.0f + 0.5f));
}

float range_from_raw_mm(std::uint16_t raw) {
  if (raw == kNoReturnRaw) return __builtin_inff();
  return static_cast<float>(raw) * kScanDataSignals[kRange0].factor;
}

CodecStatus encode(const ScanHeaderMsg& m, CanFrame& f) {
  FrameWriter w(f, kScanHeaderId, kScanHeaderSignals);
  w.integer(kHeaderScanId, m.scan_id);
  w.integer(kRangeCount, m.range_count);
  w.integer(kScanCrc, m.scan_crc);
  w.physical(kScanTime, m.scan_time_s);
  w.physical(kRangeMax, m.range_max_m);
  return w.status();
}

CodecStatus encode(const ScanInfoMsg& m, CanFrame& f) {
  FrameWriter w(f, kScanInfoId, kScanInfoSignals);
  w.integer(kInfoScanId, m.scan_id);
  w.physical(kRangeMin, m.range_min_m);
  w.physical(kAngleMin, m.angle_min_rad);
  w.physical(kAngleIncrement, m.angle_increment_rad);
  return w.status();
}

CodecStatus encode(const ScanDataMsg& m, CanFrame& f) {
  FrameWriter w(f, kScanDataId, kScanDataSignals);
  w.integer(kDataScanId, m.scan_id);
  w.integer(kSeq, m.seq);
  w.integer(kRange0, m.range_mm[0]);
  w.integer(kRange1, m.range_mm[1]);
  w.integer(kRange2, m.range_mm[2]);
  return w.status();
}

CodecStatus decode(const CanFrame& f, ScanHeaderMsg& m) {
  const CodecStatus c = check_frame(f, kScanHeaderId);
  if (c != CodecStatus::ok) return c;
  m.scan_id = raw_u8(f, kScanHeaderSignals[kHeaderScanId]);
  m.range_count = raw_u16(f, kScanHeaderSignals[kRangeCount]);
  m.scan_crc = raw_u16(f, kScanHeaderSignals[kScanCrc]);
  m.scan_time_s = decode_physical(f.data, kScanHeaderSignals[kScanTime]);
  m.range_max_m = decode_physical(f.data, kScanHeaderSignals[kRangeMax]);
  return CodecStatus::ok;
}

CodecStatus decode(const CanFrame& f, ScanInfoMsg& m) {
  const CodecStatus c = check_frame(f, kScanInfoId);
  if (c != CodecStatus::ok) return c;
  m.scan_id = raw_u8(f, kScanInfoSignals[kInfoScanId]);
  m.range_min_m = decode_physical(f.data, kScanInfoSignals[kRangeMin]);
  m.angle_min_rad = decode_physical(f.data, kScanInfoSignals[kAngleMin]);
  m.angle_increment_rad = decode_physical(f.data, kScanInfoSignals[kAngleIncrement]);
  return CodecStatus::ok;
}

CodecStatus decode(const CanFrame& f, ScanDataMsg& m) {
  const CodecStatus c = check_frame(f, kScanDataId);
  if (c != CodecStatus::ok) return c;
  m.scan_id = raw_u8(f, kScanDataSignals[kDataScanId]);
  m.seq = raw_u16(f, kScanDataSignals[kSeq]);
  m.range_mm[0] = raw_u16(f, kScanDataSignals[kRange0]);
  m.range_mm[1] = raw_u16(f, kScanDataSignals[kRange1]);
  m.range_mm[2] = raw_u16(f, kScanDataSignals[kRange2]);
  return CodecStatus::ok;
}


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
