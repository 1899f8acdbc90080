// The steering validator (hal/sensors/steering/validator.hpp).
#include "hal/sensors/steering/validator.hpp"

namespace hal {

Fault SteeringValidator::check(const SteeringSample& sample, TimeNs now_ns, SteeringSample& out) {
  Fault f = Fault::none;
  if (!__builtin_isfinite(sample.angle_rad))
    f = Fault::not_finite;
  else if (sample.angle_rad > limits_.max_angle_rad || sample.angle_rad < -limits_.max_angle_rad)
    f = Fault::out_of_range;
  else
    f = timing_.check(sample.stamp_ns, now_ns);
  if (f != Fault::none) {
    faults_.add(f);
    return f;
  }
  timing_.accept(sample.stamp_ns);
  out = sample;
  return Fault::none;
}

}  // namespace hal
