// Odometry frames (hal/sensors/odometry/can.hpp).
#include "hal/sensors/odometry/can.hpp"

#include "est/math/fmath.hpp"

namespace hal::can {

using namespace dbc;

CodecStatus encode(const OdometryMsg& m, CanFrame& f) {
  FrameWriter w(f, kOdometryId, kOdometrySignals);
  w.integer(kOdomX, m.x_mm & 0x3FFFFu);
  w.integer(kOdomY, m.y_mm & 0x3FFFFu);
  w.integer(kOdomTheta, m.theta);
  w.integer(kOdomCounter, counter4(m.counter));
  w.checksum(kOdomChecksum);
  return w.status();
}

CodecStatus decode(const CanFrame& f, OdometryMsg& m) {
  const CodecStatus c = check_frame(f, kOdometryId, kOdometrySignals[kOdomChecksum]);
  if (c != CodecStatus::ok) return c;
  m.x_mm = static_cast<std::uint32_t>(extract_raw(f.data, kOdometrySignals[kOdomX]));
  m.y_mm = static_cast<std::uint32_t>(extract_raw(f.data, kOdometrySignals[kOdomY]));
  m.theta = raw_u16(f, kOdometrySignals[kOdomTheta]);
  m.counter = raw_u8(f, kOdometrySignals[kOdomCounter]);
  return CodecStatus::ok;
}

namespace {
// v modulo period, as a count of `step` in [0, 2^bits).
std::uint32_t wrap_count(float v, float step, std::uint32_t bits) {
  const float n = v / step;
  const float period = static_cast<float>(1u << bits);
  float r = n - period * __builtin_floorf(n / period);
  if (!(r < period)) r = 0.0f;
  std::uint32_t c = static_cast<std::uint32_t>(r + 0.5f);
  return c & ((1u << bits) - 1u);
}
}  // namespace

bool to_message(const OdometrySample& s, std::uint8_t counter, OdometryMsg& m) {
  if (!s.pose.is_finite()) return false;
  m.x_mm = wrap_count(s.pose.x, 0.001f, 18);
  m.y_mm = wrap_count(s.pose.y, 0.001f, 18);
  m.theta = static_cast<std::uint16_t>(wrap_count(s.pose.theta, kOdometryThetaStep, 16));
  m.counter = counter;
  return true;
}

OdometrySample to_sample(const OdometryMsg& m, TimeNs stamp_ns) {
  OdometrySample s;
  s.stamp_ns = stamp_ns;
  s.pose.x = static_cast<float>(m.x_mm) * 0.001f;
  s.pose.y = static_cast<float>(m.y_mm) * 0.001f;
  s.pose.theta = est::fmath::normalize_angle(static_cast<float>(m.theta) * kOdometryThetaStep);
  s.wrap_m = kOdometryWrapM;
  return s;
}

}  // namespace hal::can
