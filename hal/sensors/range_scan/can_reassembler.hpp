#pragma once
// Rebuilds rangefinder scans from SCAN_HEADER / SCAN_INFO / SCAN_DATA frames, in bounded memory (one scan of at most
// K beams) and bounded time per frame. The frames of one scan must arrive in order (one sender, one bus: CAN keeps
// the order); anything else is rejected with a counted reason and the rest of that scan is dropped.
#include <cstddef>
#include <cstdint>

#include "hal/can/crc.hpp"
#include "hal/can/frame.hpp"
#include "hal/fault.hpp"
#include "hal/sensors/range_scan/range_scan.hpp"
#include "hal/time.hpp"

namespace hal::can {

enum class ScanReject : std::uint8_t {
  none = 0,
  wrong_dlc,         // a scan frame that is not 8 bytes
  orphan_frame,      // SCAN_INFO / SCAN_DATA with no scan in progress (its header was lost)
  sequence_gap,      // a frame of the scan was lost (Seq skipped, or SCAN_INFO missing)
  truncated,         // a new SCAN_HEADER before the scan in progress was complete
  duplicate_frame,   // a frame received twice (dropped; the scan goes on)
  interleaved,       // a frame of another scan id in the middle of a scan
  extra_frame,       // Seq beyond the frame count the header announced
  exceeds_capacity,  // RangeCount larger than this reassembler holds (a burst it cannot take)
  bad_header,        // RangeCount of zero
  bad_checksum,      // ScanCrc does not match the frames received
  timeout,           // the scan did not complete within the time limit
  kCount
};

const char* to_string(ScanReject r);

using ScanRejectCounters = ReasonCounters<ScanReject>;

class ScanReassemblerBase {
 public:
  struct Result {
    bool complete = false;                   // scan() holds a new scan
    ScanReject reject = ScanReject::none;    // a scan (or this frame) was rejected
  };

  ScanReassemblerBase(const ScanReassemblerBase&) = delete;
  ScanReassemblerBase& operator=(const ScanReassemblerBase&) = delete;

  static bool is_scan_frame(std::uint32_t id);

  // stamp_ns: receive time of the frame; a scan is stamped with the receive time of its header.
  Result on_frame(const CanFrame& frame, TimeNs stamp_ns);
  // Rejects a scan in progress for longer than the timeout.
  ScanReject poll(TimeNs now_ns);

  // The last completed scan; valid until the next frame is given.
  RangeScanView scan() const { return {stamp_ns_, geometry_, storage_, count_}; }

  const ScanRejectCounters& rejects() const { return rejects_; }
  std::uint32_t frames_dropped() const { return frames_dropped_; }  // frames of scans already rejected
  std::uint32_t scans_completed() const { return scans_completed_; }
  std::size_t capacity() const { return capacity_; }

 protected:
  ScanReassemblerBase(float* storage, std::size_t capacity, TimeNs timeout_ns)
      : storage_(storage), capacity_(capacity), timeout_ns_(timeout_ns) {}
  ~ScanReassemblerBase() = default;

 private:
  enum class State : std::uint8_t { idle, want_info, want_data, complete, discarding };

  bool in_progress() const { return state_ == State::want_info || state_ == State::want_data; }
  ScanReject abort(ScanReject why);
  Result on_header(const CanFrame& frame, TimeNs stamp_ns);
  // What an info or data frame meets before its own checks: no scan begun, another scan's frame, or a scan being
  // discarded. True, with the frame's result in `out`, when it stops there.
  bool stops_before(std::uint8_t scan_id, Result& out);
  Result on_info(const CanFrame& frame);
  Result on_data(const CanFrame& frame);
  Result count(ScanReject why) {
    rejects_.add(why);
    return {false, why};
  }

  float* storage_;
  std::size_t capacity_;
  TimeNs timeout_ns_;

  State state_ = State::idle;
  std::uint8_t scan_id_ = 0;
  std::uint8_t header_bytes_[8] = {};
  std::uint8_t info_bytes_[8] = {};
  std::uint16_t expected_crc_ = 0;
  std::size_t count_ = 0;
  std::size_t frames_expected_ = 0;
  std::size_t next_seq_ = 0;
  TimeNs stamp_ns_ = 0;
  ScanGeometry geometry_;
  Crc16Ccitt crc_;

  ScanRejectCounters rejects_;
  std::uint32_t frames_dropped_ = 0;
  std::uint32_t scans_completed_ = 0;
};

template <std::size_t K>
class ScanReassembler final : public ScanReassemblerBase {
 public:
  static_assert(K > 0 && K <= 4095, "RangeCount is 12 bits");
  explicit ScanReassembler(TimeNs timeout_ns = 150 * kNsPerMs) : ScanReassemblerBase(storage_, K, timeout_ns) {}

 private:
  float storage_[K] = {};
};

}  // namespace hal::can
