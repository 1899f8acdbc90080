#pragma once
// Checks odometry poses and differences them into increments: finite, within the coordinate range, fresh and
// monotonic, and moving no faster than the base can (a jump is an odometry reset: rejected as out_of_range and
// taken as the new reference, so one reset costs one interval, as a wheel counter's glitch does).
#include "hal/fault.hpp"
#include "hal/sample_validator.hpp"
#include "hal/sensors/odometry/odometry.hpp"

namespace hal {

struct OdometryLimits {
  float max_coordinate_m = 1.0e6f;   // |x|, |y| of the odometry frame
  float max_speed_mps = 5.0f;        // translation of an increment over its dt
  float max_turn_rate_rps = 10.0f;   // rotation of an increment over its dt
  TimeNs max_gap_ns = 500 * kNsPerMs;  // after a longer gap the motion is unknown: start afresh
  TimingLimits timing;
};

class OdometryValidator : public SampleValidator<OdometryLimits> {
 public:
  using Limits = OdometryLimits;
  static constexpr const char* kName = "odometry";

  explicit OdometryValidator(const OdometryLimits& limits = {}) : SampleValidator(limits) {}

  Fault check(const OdometrySample& sample, TimeNs now_ns, OdometryDelta& out);

 private:
  OdometrySample last_;
};

}  // namespace hal
