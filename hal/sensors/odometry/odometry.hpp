#pragma once
// Odometry of a base that integrates its own motion (CARMEN's ODOM lines, a ROS base's odom frame): the pose of
// the base in its odometry frame, which drifts against the world. The HAL differences consecutive poses into the
// increments the loop uses (est::loop::OdometryInput: x_bar_{t-1} (-) x_bar_t, Thrun table 5.6), so a lost sample
// costs nothing but resolution: the next increment spans both intervals.
//
// On the CAN bus the position is sent as wrapping fixed-point counters (ODOMETRY, estimator.dbc): then wrap_m is
// their period and positions are differenced modulo it, as wheel counters are; 0 when the position does not wrap.
#include "est/geometry/pose2.hpp"
#include "est/loop/inputs.hpp"
#include "hal/time.hpp"

namespace hal {

struct OdometrySample {
  TimeNs stamp_ns = 0;
  est::Pose2 pose;     // m, m, rad in the odometry frame
  float wrap_m = 0.0f; // period of x and y (0: they do not wrap)
};

// The odometry increment since the previous accepted sample, over dt_ns (identity and 0 for the first sample), and
// the sample it was differenced from (what a recorder writes, so that a replay differences the same poses).
struct OdometryDelta {
  TimeNs stamp_ns = 0;
  TimeNs dt_ns = 0;
  est::Pose2 increment;
  OdometrySample source;
};

template <typename Push>
void to_loop_inputs(const OdometryDelta& d, Push&& push) {
  push(est::loop::OdometryInput{d.stamp_ns, d.increment});
}

}  // namespace hal
