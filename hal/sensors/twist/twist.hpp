#pragma once
// A body twist, commanded (what the base was told) or measured (what its controller reports): forward speed v1,
// leftward speed v2 and yaw rate w in the robot's frame, held from the stamp until the next sample. The velocity
// model takes (v1, w); the omnidirectional model (v1, v2, w); the holonomic robot (u_x, u_y) = (v1, v2).
#include "est/loop/inputs.hpp"
#include "hal/time.hpp"

namespace hal {

struct TwistSample {
  TimeNs stamp_ns = 0;
  float v1_mps = 0.0f;
  float v2_mps = 0.0f;
  float w_rps = 0.0f;
};

template <typename Push>
void to_loop_inputs(const TwistSample& s, Push&& push) {
  push(est::loop::TwistInput{s.stamp_ns, s.v1_mps, s.v2_mps, s.w_rps});
}

}  // namespace hal
