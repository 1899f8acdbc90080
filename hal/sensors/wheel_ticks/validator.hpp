#pragma once
// Checks raw encoder samples and turns them into tick increments, handling the hardware counter's wrap-around.
#include <cstdint>

#include "hal/fault.hpp"
#include "hal/sample_validator.hpp"
#include "hal/sensors/wheel_ticks/wheel_ticks.hpp"

namespace hal {

struct WheelTicksLimits {
  std::uint8_t wheel_count = 2;            // the robot's encoders: a sample with another count is out_of_range
  std::uint8_t counter_bits = 16;          // width of the hardware counter (16 for the CAN message, 32 for LCM)
  std::uint32_t max_ticks_per_s = 20000;   // above any physical wheel speed; also bounds the wrap ambiguity
  TimeNs max_gap_ns = 500 * kNsPerMs;      // a longer gap may hide whole counter turns: start afresh
  TimingLimits timing;
};

class WheelTicksValidator : public SampleValidator<WheelTicksLimits> {
 public:
  using Limits = WheelTicksLimits;
  static constexpr const char* kName = "wheel_ticks";

  explicit WheelTicksValidator(const WheelTicksLimits& limits = {}) : SampleValidator(limits) {}

  // Fault::none: `out` holds the ticks since the previous accepted sample (zero ticks and dt for the first one, and
  // after a gap longer than max_gap_ns, whose motion is unknown: the loop sees the gap as an encoder timeout).
  // A counter that jumped faster than max_ticks_per_s is rejected as out_of_range and becomes the new reference,
  // so one glitch costs one interval of odometry, not every sample after it.
  Fault check(const WheelTicks& sample, TimeNs now_ns, WheelTickDelta& out);

 private:
  WheelTicks last_;
};

}  // namespace hal
