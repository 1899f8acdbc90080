#pragma once
// The motion the loop hands to a prediction: everything the motion inputs said since the previous prediction, from
// which each model's control assembler (est/loop/control_assembler.hpp) takes what it uses. MotionGather builds it:
//  - encoder ticks (increments): summed per wheel;
//  - odometry increments: composed, x_bar_{t-1} (-) x_bar_t over the whole interval;
//  - steering (held): the latest sample (sample and hold);
//  - twist (held): the time average over the interval of the twist held piecewise from each sample's stamp, so a
//    twist that changed within the interval counts for the time it held.
// An increment that spans a correction's time is split there (linear in time): the share up to the correction is
// taken into the motion and the rest stays queued, so the motion of an encoder period (or of a bus outage) is not
// applied after the correction instead of before it.
#include <cstdint>

#include "est/geometry/pose2.hpp"
#include "est/loop/input_queue.hpp"
#include "est/loop/inputs.hpp"

namespace est::loop {

struct Twist {
  float v1_mps = 0.0f;
  float v2_mps = 0.0f;
  float w_rps = 0.0f;
};

struct MotionInput {
  float dt_s = 0.0f;
  std::uint8_t wheel_count = 0;          // wheels of the latest encoder sample (0: none yet)
  std::int32_t ticks[kMaxWheels] = {};   // increments since the previous prediction
  Pose2 odometry;                        // odometry increment since the previous prediction (identity: none)
  Twist twist;                           // mean twist over dt (zero before the first sample)
  float steering_rad = 0.0f;             // the latest steering sample
  bool steering_known = false;
  bool twist_known = false;
};

class MotionGather {
 public:
  // The loop's first applied time: increments before it are unknown motion.
  void start(TimeNs t) {
    ticks_until_ = t;
    odometry_until_ = t;
    twist_until_ = t;
  }

  void add(const WheelTicksInput& in) {
    ticks_seen_ = true;
    wheel_count_ = in.wheel_count;
    for (std::int32_t w = 0; w < kMaxWheels; ++w) ticks_[w] += in.ticks[w];
    ticks_until_ = in.t_ns;
  }
  void add(const OdometryInput& in) {
    odometry_seen_ = true;
    odometry_ = compose(odometry_, in.increment);
    odometry_until_ = in.t_ns;
  }
  void add(const SteeringInput& in) {
    steering_ = in.angle_rad;
    steering_known_ = true;
  }
  void add(const TwistInput& in) {
    integrate_twist(in.t_ns);
    twist_ = {in.v1_mps, in.v2_mps, in.w_rps};
    twist_known_ = true;
  }

  // The share up to t of the next queued increment that spans t (null: none queued).
  void take_ticks_share(QueuedInput* next, TimeNs t) {
    if (next == nullptr || !ticks_seen_ || next->t_ns <= t || t <= ticks_until_) return;
    const float f = static_cast<float>(t - ticks_until_) / static_cast<float>(next->t_ns - ticks_until_);
    for (std::int32_t w = 0; w < kMaxWheels; ++w) {
      const std::int32_t share = static_cast<std::int32_t>(f * static_cast<float>(next->p.ticks.ticks[w]));
      ticks_[w] += share;
      next->p.ticks.ticks[w] -= share;
    }
    ticks_until_ = t;
  }
  void take_odometry_share(QueuedInput* next, TimeNs t) {
    if (next == nullptr || !odometry_seen_ || next->t_ns <= t || t <= odometry_until_) return;
    const float f = static_cast<float>(t - odometry_until_) / static_cast<float>(next->t_ns - odometry_until_);
    const Pose2& whole = next->p.odometry.increment;
    const Pose2 share{f * whole.x, f * whole.y, f * whole.theta};
    odometry_ = compose(odometry_, share);
    next->p.odometry.increment = between(share, whole);  // share (+) rest = whole
    odometry_until_ = t;
  }
  // The motion over (from, to].
  MotionInput motion(TimeNs from, TimeNs to) {
    integrate_twist(to);
    MotionInput m;
    m.dt_s = static_cast<float>(to - from) * 1.0e-9f;
    m.wheel_count = wheel_count_;
    for (std::int32_t w = 0; w < kMaxWheels; ++w) m.ticks[w] = ticks_[w];
    m.odometry = odometry_;
    if (twist_known_ && m.dt_s > 0.0f) {
      const float inv = 1.0f / m.dt_s;
      m.twist = {twist_sum_.v1_mps * inv, twist_sum_.v2_mps * inv, twist_sum_.w_rps * inv};
    }
    m.twist_known = twist_known_;
    m.steering_rad = steering_;
    m.steering_known = steering_known_;
    return m;
  }
  // A prediction used the motion: start the next interval empty.
  void consumed() {
    for (std::int32_t& t : ticks_) t = 0;
    odometry_ = Pose2{};
    twist_sum_ = Twist{};
  }

 private:
  void integrate_twist(TimeNs t) {
    if (twist_known_ && t > twist_until_) {
      const float dt = static_cast<float>(t - twist_until_) * 1.0e-9f;
      twist_sum_.v1_mps += twist_.v1_mps * dt;
      twist_sum_.v2_mps += twist_.v2_mps * dt;
      twist_sum_.w_rps += twist_.w_rps * dt;
    }
    if (t > twist_until_) twist_until_ = t;
  }

  std::int32_t ticks_[kMaxWheels] = {};
  std::uint8_t wheel_count_ = 0;
  TimeNs ticks_until_ = 0;
  bool ticks_seen_ = false;
  Pose2 odometry_;
  TimeNs odometry_until_ = 0;
  bool odometry_seen_ = false;
  float steering_ = 0.0f;
  bool steering_known_ = false;
  Twist twist_;        // held since twist_until_ (the integral covers up to there)
  Twist twist_sum_;    // integral of the held twist over the interval, m and rad
  TimeNs twist_until_ = 0;
  bool twist_known_ = false;
};

}  // namespace est::loop
