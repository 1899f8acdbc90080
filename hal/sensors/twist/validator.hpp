#pragma once
// Checks twists: finite, within the base's speed and turn-rate limits, fresh, monotonic.
#include "hal/fault.hpp"
#include "hal/sample_validator.hpp"
#include "hal/sensors/twist/twist.hpp"

namespace hal {

struct TwistLimits {
  float max_speed_mps = 5.0f;      // |v1| and |v2|
  float max_turn_rate_rps = 10.0f; // |w|
  TimingLimits timing;
};

class TwistValidator : public SampleValidator<TwistLimits> {
 public:
  using Limits = TwistLimits;
  static constexpr const char* kName = "twist";

  explicit TwistValidator(const TwistLimits& limits = {}) : SampleValidator(limits) {}

  Fault check(const TwistSample& sample, TimeNs now_ns, TwistSample& out);
};

}  // namespace hal
