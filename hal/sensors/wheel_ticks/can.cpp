// Wheel encoder frames (hal/sensors/wheel_ticks/can.hpp).
#include "hal/sensors/wheel_ticks/can.hpp"

namespace hal::can {

using namespace dbc;

CodecStatus encode(const WheelTicksMsg& m, CanFrame& f) {
  FrameWriter w(f, kWheelTicksId, kWheelTicksSignals);
  // WheelCount's DBC range is [1, 4], narrower than its 3 bits: FrameWriter::integer checks only the bits.
  if (m.wheel_count < 1u || m.wheel_count > kMaxWheels) return CodecStatus::out_of_range;
  w.integer(kTicks0, m.ticks[0]);
  w.integer(kTicks1, m.ticks[1]);
  w.integer(kWheelCount, m.wheel_count);
  w.integer(kWheelCounter, counter4(m.counter));
  w.checksum(kWheelChecksum);
  return w.status();
}

CodecStatus encode(const WheelTicksExtMsg& m, CanFrame& f) {
  FrameWriter w(f, kWheelTicksExtId, kWheelTicksExtSignals);
  w.integer(kTicks2, m.ticks[0]);
  w.integer(kTicks3, m.ticks[1]);
  w.integer(kWheelExtCounter, counter4(m.counter));
  w.checksum(kWheelExtChecksum);
  return w.status();
}

CodecStatus decode(const CanFrame& f, WheelTicksMsg& m) {
  const CodecStatus c = check_frame(f, kWheelTicksId, kWheelTicksSignals[kWheelChecksum]);
  if (c != CodecStatus::ok) return c;
  m.ticks[0] = raw_u16(f, kWheelTicksSignals[kTicks0]);
  m.ticks[1] = raw_u16(f, kWheelTicksSignals[kTicks1]);
  m.wheel_count = raw_u8(f, kWheelTicksSignals[kWheelCount]);
  m.counter = raw_u8(f, kWheelTicksSignals[kWheelCounter]);
  return CodecStatus::ok;
}

CodecStatus decode(const CanFrame& f, WheelTicksExtMsg& m) {
  const CodecStatus c = check_frame(f, kWheelTicksExtId, kWheelTicksExtSignals[kWheelExtChecksum]);
  if (c != CodecStatus::ok) return c;
  m.ticks[0] = raw_u16(f, kWheelTicksExtSignals[kTicks2]);
  m.ticks[1] = raw_u16(f, kWheelTicksExtSignals[kTicks3]);
  m.counter = raw_u8(f, kWheelTicksExtSignals[kWheelExtCounter]);
  return CodecStatus::ok;
}

std::size_t encode_wheel_ticks(const WheelTicks& s, std::uint8_t counter, CanFrame (&out)[2]) {
  if (s.wheel_count < 1u || s.wheel_count > kMaxWheels) return 0;
  WheelTicksMsg first;
  first.wheel_count = s.wheel_count;
  first.counter = counter;
  for (std::size_t w = 0; w < 2; ++w) first.ticks[w] = static_cast<std::uint16_t>(s.count[w] & 0xFFFFu);
  if (encode(first, out[0]) != CodecStatus::ok) return 0;
  if (s.wheel_count <= 2u) return 1;
  WheelTicksExtMsg second;
  second.counter = counter;
  for (std::size_t w = 0; w < 2; ++w) second.ticks[w] = static_cast<std::uint16_t>(s.count[2 + w] & 0xFFFFu);
  return encode(second, out[1]) == CodecStatus::ok ? 2 : 0;
}

WheelTicksFrames::Result WheelTicksFrames::on_first(const WheelTicksMsg& m, TimeNs stamp_ns, WheelTicks& out) {
  Result r;
  r.incomplete = waiting_;
  waiting_ = false;
  WheelTicks s;
  s.stamp_ns = stamp_ns;
  s.wheel_count = m.wheel_count;
  s.count[0] = m.ticks[0];
  s.count[1] = m.ticks[1];
  if (m.wheel_count <= 2u) {
    out = s;
    r.sample = true;
    return r;
  }
  pending_ = s;
  pending_counter_ = m.counter;
  waiting_ = true;
  return r;
}

WheelTicksFrames::Result WheelTicksFrames::on_second(const WheelTicksExtMsg& m, WheelTicks& out) {
  Result r;
  if (!waiting_ || m.counter != pending_counter_) {
    waiting_ = false;
    r.incomplete = true;
    return r;
  }
  waiting_ = false;
  out = pending_;
  out.count[2] = m.ticks[0];
  out.count[3] = m.ticks[1];
  r.sample = true;
  return r;
}

}  // namespace hal::can
