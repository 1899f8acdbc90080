#pragma once
// Velocity model (Thrun table 5.3): the twist's (v1, w), averaged over the interval, is the commanded (v, w) held
// for dt; a sideways v2 has no place in this model and is ignored.
#include "est/loop/control_assembler.hpp"
#include "est/motion/velocity_model.hpp"

namespace est::loop {

template <>
struct ControlAssembler<VelocityMotionModel> {
  struct Config {};
  static InputKinds inputs(const Config&) { return InputKind::twist; }
  static ControlStatus make(const MotionInput& m, const Config&, VelocityParams& p, VelocityControl& u) {
    if (!m.twist_known || (m.twist.v1_mps == 0.0f && m.twist.w_rps == 0.0f)) return ControlStatus::still;
    if (!(m.dt_s > 0.0f)) return ControlStatus::rejected;
    p.dt = m.dt_s;
    u = {m.twist.v1_mps, m.twist.w_rps};
    return ControlStatus::ok;
  }
};

}  // namespace est::loop
