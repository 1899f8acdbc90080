// The sender's side of the bus (hal/can/sample_frames.hpp).
#include "hal/can/sample_frames.hpp"

#include "hal/sensors/odometry/can.hpp"
#include "hal/sensors/range_scan/can_frames.hpp"
#include "hal/sensors/steering/can.hpp"
#include "hal/sensors/twist/can.hpp"
#include "hal/sensors/wheel_ticks/can.hpp"

namespace hal::can {

std::size_t SampleFrames::encode(const WheelTicks& s, CanFrame* out, std::size_t max) {
  CanFrame f[2];
  const std::size_t n = encode_wheel_ticks(s, wheels_, f);
  if (n == 0 || n > max) return 0;
  next(wheels_);
  for (std::size_t i = 0; i < n; ++i) out[i] = f[i];
  return n;
}

std::size_t SampleFrames::encode(const SteeringSample& s, CanFrame* out, std::size_t max) {
  if (max < 1 || can::encode(to_message(s, steering_), out[0]) != CodecStatus::ok) return 0;
  next(steering_);
  return 1;
}

std::size_t SampleFrames::encode(const TwistSample& s, CanFrame* out, std::size_t max) {
  if (max < 1 || can::encode(to_message(s, twist_), out[0]) != CodecStatus::ok) return 0;
  next(twist_);
  return 1;
}

std::size_t SampleFrames::encode(const OdometrySample& s, CanFrame* out, std::size_t max) {
  OdometryMsg m;
  if (max < 1 || !to_message(s, odometry_, m) || can::encode(m, out[0]) != CodecStatus::ok) return 0;
  next(odometry_);
  return 1;
}

std::size_t SampleFrames::encode(const RangeScanView& s, CanFrame* out, std::size_t max) {
  const ScanSplit split = split_scan(s, scan_id_, out, max);
  if (split.status != CodecStatus::ok) return 0;
  next(scan_id_);
  return split.frames;
}

}  // namespace hal::can
