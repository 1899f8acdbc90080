#pragma once
// Checks steering samples: finite, within the mechanical limit, fresh, monotonic.
#include "hal/fault.hpp"
#include "hal/sample_validator.hpp"
#include "hal/sensors/steering/steering.hpp"

namespace hal {

struct SteeringLimits {
  float max_angle_rad = 0.7f;  // mechanical stop of the steering linkage
  TimingLimits timing;
};

class SteeringValidator : public SampleValidator<SteeringLimits> {
 public:
  using Limits = SteeringLimits;
  static constexpr const char* kName = "steering";

  explicit SteeringValidator(const SteeringLimits& limits = {}) : SampleValidator(limits) {}

  Fault check(const SteeringSample& sample, TimeNs now_ns, SteeringSample& out);
};

}  // namespace hal
