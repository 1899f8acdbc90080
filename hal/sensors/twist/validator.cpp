// The twist validator (hal/sensors/twist/validator.hpp).
#include "hal/sensors/twist/validator.hpp"

namespace hal {

namespace {
bool within(float v, float limit) { return v <= limit && v >= -limit; }
}  // namespace

Fault TwistValidator::check(const TwistSample& s, TimeNs now_ns, TwistSample& out) {
  Fault f = Fault::none;
  if (!__builtin_isfinite(s.v1_mps) || !__builtin_isfinite(s.v2_mps) || !__builtin_isfinite(s.w_rps))
    f = Fault::not_finite;
  else if (!within(s.v1_mps, limits_.max_speed_mps) || !within(s.v2_mps, limits_.max_speed_mps) ||
           !within(s.w_rps, limits_.max_turn_rate_rps))
    f = Fault::out_of_range;
  else
    f = timing_.check(s.stamp_ns, now_ns);
  if (f != Fault::none) {
    faults_.add(f);
    return f;
  }
  timing_.accept(s.stamp_ns);
  out = s;
  return Fault::none;
}

}  // namespace hal
