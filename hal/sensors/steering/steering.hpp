#pragma once
// Steering angle sample: front-wheel angle of the bicycle model, radians, positive to the left.
#include "est/loop/inputs.hpp"
#include "hal/time.hpp"

namespace hal {

struct SteeringSample {
  TimeNs stamp_ns = 0;
  float angle_rad = 0.0f;
};

template <typename Push>
void to_loop_inputs(const SteeringSample& s, Push&& push) {
  push(est::loop::SteeringInput{s.stamp_ns, s.angle_rad});
}

}  // namespace hal
