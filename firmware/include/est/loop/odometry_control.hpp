#pragma once
// How the loop's encoder ticks and steering become each motion model's control. One specialization per model that
// can run on wheel encoders; the others (velocity, omni, holonomic) take commanded or fused controls instead.
#include <cstdint>

#include "est/loop/filter_loop.hpp"
#include "est/motion/bicycle_model.hpp"
#include "est/motion/diff_drive_model.hpp"

namespace est::loop {

template <typename Model>
struct OdometryControl;

// Differential drive: the tick increments are the control; the model knows wheel radius and ticks per revolution.
template <>
struct OdometryControl<DiffDriveMotionModel> {
  static constexpr bool kUsesSteering = false;
  struct Config {};
  static Config config(float) { return {}; }  // the travel per tick is the model's (wheel radius, ticks per rev)
  static bool make(const MotionInput& m, const Config&, DiffDriveMotionModel::Params&,
                   DiffDriveMotionModel::Control& u) {
    u = {m.left_ticks, m.right_ticks};
    return true;
  }
};

// Bicycle (front-wheel referenced): a traction encoder on the front wheel (the left channel) gives the wheel's
// travel over dt, the steering sensor gives a; the speed is travel / dt, held over dt.
template <>
struct OdometryControl<BicycleMotionModel> {
  static constexpr bool kUsesSteering = true;
  struct Config {
    float metres_per_tick = 0.001f;
  };
  static Config config(float metres_per_tick) { return {metres_per_tick}; }
  static bool make(const MotionInput& m, const Config& c, BicycleMotionModel::Params& p,
                   BicycleMotionModel::Control& u) {
    if (!(m.dt_s > 0.0f)) return false;
    p.dt = m.dt_s;
    u.v = static_cast<float>(m.left_ticks) * c.metres_per_tick / m.dt_s;
    u.steer = m.steering_known ? m.steering_rad : 0.0f;
    return true;
  }
};

}  // namespace est::loop
