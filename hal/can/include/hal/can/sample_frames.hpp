#pragma once
// The sender's side of estimator.dbc for any raw sample: the frames a sensor puts on the bus, with each message's
// alive counter kept here (the simulator, can_player, tests; a board's sensor drivers would do the same). Each
// sensor's frames are its codec's (hal/sensors/<sensor>/can.hpp).
#include <cstddef>
#include <cstdint>

#include "hal/can/frame.hpp"
#include "hal/sensors/landmarks/landmarks.hpp"
#include "hal/sensors/odometry/odometry.hpp"
#include "hal/sensors/range_scan/range_scan.hpp"
#include "hal/sensors/steering/steering.hpp"
#include "hal/sensors/twist/twist.hpp"
#include "hal/sensors/wheel_ticks/wheel_ticks.hpp"

namespace hal::can {

class SampleFrames {
 public:
  // Writes the frames of one sample into out (room for max); returns how many, 0 when the sample does not fit the
  // bus (its range, a scan too long for `max`) or has no frame (landmark sightings travel on LCM).
  std::size_t encode(const WheelTicks& s, CanFrame* out, std::size_t max);
  std::size_t encode(const SteeringSample& s, CanFrame* out, std::size_t max);
  std::size_t encode(const TwistSample& s, CanFrame* out, std::size_t max);
  std::size_t encode(const OdometrySample& s, CanFrame* out, std::size_t max);
  std::size_t encode(const RangeScanView& s, CanFrame* out, std::size_t max);
  std::size_t encode(const LandmarkSightingView&, CanFrame*, std::size_t) { return 0; }

 private:
  static std::uint8_t next(std::uint8_t& c) {
    const std::uint8_t v = c;
    c = static_cast<std::uint8_t>((c + 1u) & 0x0Fu);
    return v;
  }
  std::uint8_t wheels_ = 0, steering_ = 0, twist_ = 0, odometry_ = 0, scan_id_ = 0;
};

}  // namespace hal::can
