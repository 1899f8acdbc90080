#pragma once
// Differential drive: the two wheels' tick increments are the control (wheel 0 left, wheel 1 right); the model
// knows the wheel radius and the ticks per revolution.
#include "est/loop/control_assembler.hpp"
#include "est/motion/diff_drive_model.hpp"

namespace est::loop {

template <>
struct ControlAssembler<DiffDriveMotionModel> {
  struct Config {};
  static InputKinds inputs(const Config&) { return InputKind::wheel_ticks; }
  static ControlStatus make(const MotionInput& m, const Config&, DiffDriveParams&, DiffDriveControl& u) {
    if (m.ticks[0] == 0 && m.ticks[1] == 0) return ControlStatus::still;
    if (m.wheel_count < 2u) return ControlStatus::rejected;
    u = {m.ticks[0], m.ticks[1]};
    return ControlStatus::ok;
  }
};

}  // namespace est::loop
