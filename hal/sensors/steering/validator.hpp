#pragma once
// Checks steering samples: finite, within the mechanical limit, fresh, monotonic.
#include "hal/fault.hpp"
#include "hal/sample_timing.hpp"
#include "hal/sensors/steering/steering.hpp"

namespace hal {

struct SteeringLimits {
  float max_angle_rad = 0.7f;  // mechanical stop of the steering linkage
  TimingLimits timing;
};

class SteeringValidator {
 public:
  using Limits = SteeringLimits;
  static constexpr const char* kName = "steering";

  explicit SteeringValidator(const SteeringLimits& limits = {}) : limits_(limits), timing_(limits.timing) {}

  Fault check(const SteeringSample& sample, TimeNs now_ns, SteeringSample& out);

  const FaultCounters& faults() const { return faults_; }

 private:
  SteeringLimits limits_;
  SampleTiming timing_;
  FaultCounters faults_;
};

}  // namespace hal
