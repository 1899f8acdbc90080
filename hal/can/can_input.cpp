// The CAN receive path (hal/can/can_input.hpp).
#include "hal/can/can_input.hpp"

#include "hal/can/estimator_dbc.hpp"
#include "hal/can/messages.hpp"

namespace hal::can {

const char* to_string(FrameReject r) {
  switch (r) {
    case FrameReject::none: return "none";
    case FrameReject::unknown_id: return "unknown_id";
    case FrameReject::wrong_dlc: return "wrong_dlc";
    case FrameReject::bad_checksum: return "bad_checksum";
    case FrameReject::duplicate: return "duplicate";
    case FrameReject::counter_gap: return "counter_gap";
    case FrameReject::kCount: break;
  }
  return "unknown";
}

bool CanInput::check_alive(Alive& a, std::uint8_t counter) {
  if (a.seen && counter == a.last) {
    rejects_.add(FrameReject::duplicate);
    return false;
  }
  if (a.seen && counter != ((a.last + 1u) & 0x0Fu)) rejects_.add(FrameReject::counter_gap);
  a.seen = true;
  a.last = counter;
  return true;
}

void CanInput::on_frame(const CanFrame& frame, TimeNs stamp_ns) {
  if (ScanReassemblerBase::is_scan_frame(frame.id)) {
    const ScanReassemblerBase::Result r = scans_.on_frame(frame, stamp_ns);
    if (r.reject == ScanReject::none) ++frames_accepted_;
    if (r.complete) port_.on_range_scan(scans_.scan());
    return;
  }
  CodecStatus status = CodecStatus::wrong_id;
  if (frame.id == dbc::kWheelTicksId) {
    WheelTicksMsg m;
    status = decode(frame, m);
    if (status == CodecStatus::ok && check_alive(wheels_alive_, m.counter)) {
      WheelTicks s;
      s.stamp_ns = stamp_ns;
      s.wheel_count = 2;
      s.count[0] = m.ticks_left;
      s.count[1] = m.ticks_right;
      ++frames_accepted_;
      port_.on_wheel_ticks(s);
    }
  } else if (frame.id == dbc::kSteeringId) {
    SteeringMsg m;
    status = decode(frame, m);
    if (status == CodecStatus::ok && check_alive(steering_alive_, m.counter)) {
      ++frames_accepted_;
      port_.on_steering({stamp_ns, m.angle_rad});
    }
  }
  switch (status) {
    case CodecStatus::wrong_id: rejects_.add(FrameReject::unknown_id); break;
    case CodecStatus::wrong_dlc: rejects_.add(FrameReject::wrong_dlc); break;
    case CodecStatus::bad_checksum: rejects_.add(FrameReject::bad_checksum); break;
    default: break;
  }
}

}  // namespace hal::can
