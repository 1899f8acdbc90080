#pragma once
// Bicycle (front-wheel referenced): the traction encoder on the front wheel gives the wheel's travel over dt, the
// steering sensor the angle a; the speed is travel / dt, held over dt. Without a steering angle (no sensor fitted,
// none received yet, and no estimate from the estimator) the steering is taken as 0 and, if unknown_steer_sigma > 0,
// known only to that standard deviation (the filter then has to find the turns from its measurements).
#include <cstdint>

#include "est/loop/control_assembler.hpp"
#include "est/motion/bicycle_model.hpp"

namespace est::loop {

template <>
struct ControlAssembler<BicycleMotionModel> {
  struct Config {
    float metres_per_tick = 0.001f;  // front-wheel travel per tick
    std::uint8_t traction_wheel = 0; // the encoder of the front wheel
    bool steering_fitted = true;
    float unknown_steer_sigma = 0.0f;  // rad; 0: the configured steer_sigma
  };
  static InputKinds inputs(const Config& c) {
    return c.steering_fitted ? InputKind::wheel_ticks | InputKind::steering : InputKinds(InputKind::wheel_ticks);
  }
  static ControlStatus make(const MotionInput& m, const Config& c, BicycleParams& p, BicycleControl& u) {
    if (c.traction_wheel >= kMaxWheels) return ControlStatus::rejected;
    const std::int32_t ticks = m.ticks[c.traction_wheel];
    if (ticks == 0) return ControlStatus::still;
    if (m.wheel_count <= c.traction_wheel || !(m.dt_s > 0.0f)) return ControlStatus::rejected;
    p.dt = m.dt_s;
    u.v = static_cast<float>(ticks) * c.metres_per_tick / m.dt_s;
    const bool known = m.steering_known;  // without a sensor fitted, only an estimator's estimate sets it
    u.steer = known ? m.steering_rad : 0.0f;
    if (!known && c.unknown_steer_sigma > p.steer_sigma) p.steer_sigma = c.unknown_steer_sigma;
    return ControlStatus::ok;
  }
};

}  // namespace est::loop
