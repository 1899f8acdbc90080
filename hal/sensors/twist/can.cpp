// Twist frames (hal/sensors/twist/can.hpp).
#include "hal/sensors/twist/can.hpp"

namespace hal::can {

using namespace dbc;

CodecStatus encode(const TwistMsg& m, CanFrame& f) {
  FrameWriter w(f, kTwistId, kTwistSignals);
  w.physical(kTwistV1, m.v1_mps);
  w.physical(kTwistV2, m.v2_mps);
  w.physical(kTwistW, m.w_rps);
  w.integer(kTwistCounter, counter4(m.counter));
  w.checksum(kTwistChecksum);
  return w.status();
}

CodecStatus decode(const CanFrame& f, TwistMsg& m) {
  const CodecStatus c = check_frame(f, kTwistId, kTwistSignals[kTwistChecksum]);
  if (c != CodecStatus::ok) return c;
  m.v1_mps = decode_physical(f.data, kTwistSignals[kTwistV1]);
  m.v2_mps = decode_physical(f.data, kTwistSignals[kTwistV2]);
  m.w_rps = decode_physical(f.data, kTwistSignals[kTwistW]);
  m.counter = raw_u8(f, kTwistSignals[kTwistCounter]);
  return CodecStatus::ok;
}

}  // namespace hal::can
