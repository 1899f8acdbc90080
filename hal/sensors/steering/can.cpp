// Steering frames (hal/sensors/steering/can.hpp).
#include "hal/sensors/steering/can.hpp"

namespace hal::can {

using namespace dbc;

CodecStatus encode(const SteeringMsg& m, CanFrame& f) {
  FrameWriter w(f, kSteeringId, kSteeringSignals);
  w.physical(kSteeringAngle, m.angle_rad);
  w.integer(kSteeringCounter, counter4(m.counter));
  w.checksum(kSteeringChecksum);
  return w.status();
}

CodecStatus decode(const CanFrame& f, SteeringMsg& m) {
  const CodecStatus c = check_frame(f, kSteeringId, kSteeringSignals[kSteeringChecksum]);
  if (c != CodecStatus::ok) return c;
  m.angle_rad = decode_physical(f.data, kSteeringSignals[kSteeringAngle]);
  m.counter = raw_u8(f, kSteeringSignals[kSteeringCounter]);
  return CodecStatus::ok;
}

}  // namespace hal::can
