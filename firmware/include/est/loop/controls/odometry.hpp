#pragma once
// Odometry model (Thrun table 5.6): the composed odometry increment since the previous prediction is the pair
// (x_bar_{t-1}, x_bar_t) = (identity, increment); the model reads only their relative motion.
#include "est/loop/control_assembler.hpp"
#include "est/motion/odometry_model.hpp"

namespace est::loop {

template <>
struct ControlAssembler<OdometryMotionModel> {
  struct Config {};
  static InputKinds inputs(const Config&) { return InputKind::odometry; }
  static ControlStatus make(const MotionInput& m, const Config&, OdometryParams&, est::OdometryControl& u) {
    if (m.odometry.is_identity()) return ControlStatus::still;
    u = {Pose2{}, m.odometry};
    return ControlStatus::ok;
  }
};

}  // namespace est::loop
