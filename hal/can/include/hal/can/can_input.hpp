#pragma once
// The CAN receive path, for any driver (SocketCAN on the host, a controller ISR on the board): frames with their
// receive stamps in, HAL samples out to a SensorPort (usually hal::ValidatedInputs), every bad frame counted.
// Each sensor's frames are decoded by its codec (hal/sensors/<sensor>/can.hpp).
#include <cstdint>

#include "hal/can/frame.hpp"
#include "hal/fault.hpp"
#include "hal/sensor_port.hpp"
#include "hal/sensors/range_scan/can_reassembler.hpp"
#include "hal/sensors/wheel_ticks/can.hpp"

namespace hal::can {

enum class FrameReject : std::uint8_t {
  none = 0,
  unknown_id,    // not an input of estimator.dbc (a kernel filter should have dropped it)
  wrong_dlc,     // an input frame that is not 8 bytes (scan frames count theirs in ScanReject)
  bad_checksum,  // per-frame CRC-8
  duplicate,     // same alive counter as the previous frame of that id (dropped)
  counter_gap,   // alive counter skipped: frames were lost (the frame itself is accepted)
  incomplete,    // WHEEL_TICKS of three or four wheels without its WHEEL_TICKS_EXT, or the reverse (dropped)
  kCount
};

const char* to_string(FrameReject r);

using FrameRejectCounters = ReasonCounters<FrameReject>;

class CanInput {
 public:
  CanInput(ScanReassemblerBase& scans, SensorPort& port) : scans_(scans), port_(port) {}

  void on_frame(const CanFrame& frame, TimeNs stamp_ns);
  // Call at least once per loop step: times out a stalled scan.
  void poll(TimeNs now_ns) { scans_.poll(now_ns); }

  const FrameRejectCounters& rejects() const { return rejects_; }
  const ScanReassemblerBase& scans() const { return scans_; }
  std::uint32_t frames_accepted() const { return frames_accepted_; }

 private:
  // Alive counter of one periodic message (AUTOSAR E2E style): repeat = duplicate, skip = lost frames.
  struct Alive {
    bool seen = false;
    std::uint8_t last = 0;
  };
  bool check_alive(Alive& a, std::uint8_t counter);
  // Decodes a single-frame message and delivers its sample; the codec status for the reject count.
  template <typename Msg>
  CodecStatus single(const CanFrame& frame, TimeNs stamp_ns, Alive& alive);

  ScanReassemblerBase& scans_;
  SensorPort& port_;
  FrameRejectCounters rejects_;
  WheelTicksFrames wheel_frames_;
  Alive wheels_alive_, steering_alive_, twist_alive_, odometry_alive_;
  std::uint32_t frames_accepted_ = 0;
};

}  // namespace hal::can
