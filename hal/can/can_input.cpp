// The CAN receive path (hal/can/can_input.hpp).
#include "hal/can/can_input.hpp"

#include "hal/can/estimator_dbc.hpp"

namespace hal::can {

const char* to_string(FrameReject r) {
  switch (r) {
    case FrameReject::none: return "none";
    case FrameReject::unknown_id: return "unknown_id";
    case FrameReject::wrong_dlc: return "wrong_dlc";
    case FrameReject::bad_checksum: return "bad_checksum";
    case FrameReject::duplicate: return "duplicate";
    case FrameReject::counter_gap: return "counter_gap";
    case FrameReject::incomplete: return "incomplete";
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

template <typename Msg>
CodecStatus CanInput::single(const CanFrame& frame, TimeNs stamp_ns, Alive& alive) {
  Msg m;
  const CodecStatus status = decode(frame, m);
  if (status == CodecStatus::ok && check_alive(alive, m.counter)) {
    ++frames_accepted_;
    port_.on(to_sample(m, stamp_ns));
  }
  return status;
}

void CanInput::on_frame(const CanFrame& frame, TimeNs stamp_ns) {
  if (ScanReassemblerBase::is_scan_frame(frame.id)) {
    const ScanReassemblerBase::Result r = scans_.on_frame(frame, stamp_ns);
    if (r.reject == ScanReject::none) ++frames_accepted_;
    if (r.complete) port_.on(scans_.scan());
    return;
  }
  CodecStatus status = CodecStatus::wrong_id;
  WheelTicks ticks;
  WheelTicksFrames::Result pair;
  switch (frame.id) {
    case dbc::kWheelTicksId: {
      WheelTicksMsg m;
      status = decode(frame, m);
      if (status == CodecStatus::ok && check_alive(wheels_alive_, m.counter)) {
        ++frames_accepted_;
        pair = wheel_frames_.on_first(m, stamp_ns, ticks);
      }
      break;
    }
    case dbc::kWheelTicksExtId: {
      WheelTicksExtMsg m;
      status = decode(frame, m);
      if (status == CodecStatus::ok) {
        ++frames_accepted_;
        pair = wheel_frames_.on_second(m, ticks);
      }
      break;
    }
    case dbc::kSteeringId: status = single<SteeringMsg>(frame, stamp_ns, steering_alive_); break;
    case dbc::kTwistId: status = single<TwistMsg>(frame, stamp_ns, twist_alive_); break;
    case dbc::kOdometryId: status = single<OdometryMsg>(frame, stamp_ns, odometry_alive_); break;
    default: break;
  }
  if (pair.incomplete) rejects_.add(FrameReject::incomplete);
  if (pair.sample) port_.on(ticks);
  switch (status) {
    case CodecStatus::wrong_id: rejects_.add(FrameReject::unknown_id); break;
    case CodecStatus::wrong_dlc: rejects_.add(FrameReject::wrong_dlc); break;
    case CodecStatus::bad_checksum: rejects_.add(FrameReject::bad_checksum); break;
    default: break;
  }
}

}  // namespace hal::can
