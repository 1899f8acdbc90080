// Scan reassembly (hal/can/scan_reassembler.hpp): a small state machine, O(1) work per frame.
#include "hal/sensors/range_scan/can_reassembler.hpp"

#include "hal/sensors/range_scan/can_frames.hpp"

namespace hal::can {

namespace {
bool same_bytes(const std::uint8_t* a, const std::uint8_t* b) {
  for (int i = 0; i < 8; ++i)
    if (a[i] != b[i]) return false;
  return true;
}
void copy_bytes(std::uint8_t* to, const std::uint8_t* from) {
  for (int i = 0; i < 8; ++i) to[i] = from[i];
}
}  // namespace

const char* to_string(ScanReject r) {
  switch (r) {
    case ScanReject::none: return "none";
    case ScanReject::wrong_dlc: return "wrong_dlc";
    case ScanReject::orphan_frame: return "orphan_frame";
    case ScanReject::sequence_gap: return "sequence_gap";
    case ScanReject::truncated: return "truncated";
    case ScanReject::duplicate_frame: return "duplicate_frame";
    case ScanReject::interleaved: return "interleaved";
    case ScanReject::extra_frame: return "extra_frame";
    case ScanReject::exceeds_capacity: return "exceeds_capacity";
    case ScanReject::bad_header: return "bad_header";
    case ScanReject::bad_checksum: return "bad_checksum";
    case ScanReject::timeout: return "timeout";
    case ScanReject::kCount: break;
  }
  return "unknown";
}

bool ScanReassemblerBase::is_scan_frame(std::uint32_t id) {
  return id == dbc::kScanHeaderId || id == dbc::kScanInfoId || id == dbc::kScanDataId;
}

ScanReject ScanReassemblerBase::abort(ScanReject why) {
  rejects_.add(why);
  state_ = State::discarding;  // the rest of this scan id is dropped quietly (frames_dropped)
  return why;
}

ScanReject ScanReassemblerBase::poll(TimeNs now_ns) {
  if (in_progress() && now_ns - stamp_ns_ > timeout_ns_) return abort(ScanReject::timeout);
  return ScanReject::none;
}

ScanReassemblerBase::Result ScanReassemblerBase::on_frame(const CanFrame& frame, TimeNs stamp_ns) {
  if (!is_scan_frame(frame.id)) return {};
  if (frame.dlc != 8) return count(ScanReject::wrong_dlc);
  if (in_progress() && stamp_ns - stamp_ns_ > timeout_ns_) {
    const ScanReject why = abort(ScanReject::timeout);
    Result r = frame.id == dbc::kScanHeaderId ? on_header(frame, stamp_ns) : Result{};
    if (frame.id != dbc::kScanHeaderId) ++frames_dropped_;
    if (r.reject == ScanReject::none) r.reject = why;
    return r;
  }
  if (frame.id == dbc::kScanHeaderId) return on_header(frame, stamp_ns);
  if (frame.id == dbc::kScanInfoId) return on_info(frame);
  return on_data(frame);
}

ScanReassemblerBase::Result ScanReassemblerBase::on_header(const CanFrame& frame, TimeNs stamp_ns) {
  ScanHeaderMsg h;
  (void)decode(frame, h);  // id and dlc were checked: decoding a header cannot fail
  Result result;
  if (in_progress()) {
    if (h.scan_id == scan_id_ && same_bytes(frame.data, header_bytes_)) return count(ScanReject::duplicate_frame);
    result.reject = abort(ScanReject::truncated);
  } else if ((state_ == State::complete || state_ == State::discarding) && h.scan_id == scan_id_ &&
             same_bytes(frame.data, header_bytes_)) {
    return count(ScanReject::duplicate_frame);
  }
  scan_id_ = h.scan_id;
  copy_bytes(header_bytes_, frame.data);
  if (h.range_count == 0) {
    state_ = State::discarding;
    return count(ScanReject::bad_header);
  }
  if (h.range_count > capacity_) {
    state_ = State::discarding;
    return count(ScanReject::exceeds_capacity);
  }
  state_ = State::want_info;
  count_ = h.range_count;
  frames_expected_ = scan_data_frames(count_);
  next_seq_ = 0;
  expected_crc_ = h.scan_crc;
  stamp_ns_ = stamp_ns;
  geometry_ = ScanGeometry{};
  geometry_.range_max_m = h.range_max_m;
  geometry_.scan_time_s = h.scan_time_s;
  crc_ = Crc16Ccitt{};
  return result;
}

bool ScanReassemblerBase::stops_before(std::uint8_t scan_id, Result& out) {
  if (state_ == State::idle) {
    out = count(ScanReject::orphan_frame);
  } else if (scan_id != scan_id_) {
    out = in_progress() ? Result{false, abort(ScanReject::interleaved)} : count(ScanReject::orphan_frame);
  } else if (state_ == State::discarding) {
    ++frames_dropped_;
    out = {};
  } else {
    return false;
  }
  return true;
}

ScanReassemblerBase::Result ScanReassemblerBase::on_info(const CanFrame& frame) {
  ScanInfoMsg m;
  (void)decode(frame, m);
  Result stop;
  if (stops_before(m.scan_id, stop)) return stop;
  if (state_ != State::want_info) {
    if (same_bytes(frame.data, info_bytes_)) return count(ScanReject::duplicate_frame);
    return {false, in_progress() ? abort(ScanReject::sequence_gap) : ScanReject::none};
  }
  copy_bytes(info_bytes_, frame.data);
  geometry_.range_min_m = m.range_min_m;
  geometry_.angle_min_rad = m.angle_min_rad;
  geometry_.angle_increment_rad = m.angle_increment_rad;
  crc_.add(frame.data, 8);
  state_ = State::want_data;
  return {};
}

ScanReassemblerBase::Result ScanReassemblerBase::on_data(const CanFrame& frame) {
  ScanDataMsg m;
  (void)decode(frame, m);
  Result stop;
  if (stops_before(m.scan_id, stop)) return stop;
  if (state_ == State::complete) return count(ScanReject::duplicate_frame);
  if (state_ == State::want_info) return {false, abort(ScanReject::sequence_gap)};
  if (m.seq < next_seq_) return count(ScanReject::duplicate_frame);
  if (m.seq >= frames_expected_) return {false, abort(ScanReject::extra_frame)};
  if (m.seq > next_seq_) return {false, abort(ScanReject::sequence_gap)};

  for (std::size_t j = 0; j < kRangesPerDataFrame; ++j) {
    const std::size_t i = next_seq_ * kRangesPerDataFrame + j;
    if (i < count_) storage_[i] = range_from_raw_mm(m.range_mm[j]);
  }
  crc_.add(frame.data, 8);
  ++next_seq_;
  if (next_seq_ < frames_expected_) return {};
  if (crc_.value() != expected_crc_) {
    state_ = State::discarding;
    return count(ScanReject::bad_checksum);
  }
  state_ = State::complete;
  ++scans_completed_;
  return {true, ScanReject::none};
}

}  // namespace hal::can
