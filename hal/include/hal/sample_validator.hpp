#pragma once
// What every sensor's validator (hal/sensors/<sensor>/validator.hpp) has: its limits, the shared timing checks
// (hal/sample_timing.hpp, from limits.timing) and a counter per rejection reason. A validator derives from
// SampleValidator<its Limits> and adds its `Fault check(const Raw&, TimeNs now, Checked& out)`.
#include "hal/fault.hpp"
#include "hal/sample_timing.hpp"

namespace hal {

template <typename Limits>
class SampleValidator {
 public:
  const FaultCounters& faults() const { return faults_; }
  const Limits& limits() const { return limits_; }

 protected:
  explicit SampleValidator(const Limits& limits) : limits_(limits), timing_(limits.timing) {}
  ~SampleValidator() = default;

  // Counts f and returns it.
  Fault reject(Fault f) {
    faults_.add(f);
    return f;
  }

  Limits limits_;
  SampleTiming timing_;
  FaultCounters faults_;
};

}  // namespace hal
