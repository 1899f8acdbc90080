#pragma once
// Steering angle sample: front-wheel angle of the bicycle model, radians, positive to the left.
#include "hal/time.hpp"

namespace hal {

struct SteeringSample {
  TimeNs stamp_ns = 0;
  float angle_rad = 0.0f;
};

}  // namespace hal
