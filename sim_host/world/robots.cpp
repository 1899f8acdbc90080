#include "world/robots.hpp"

#include <algorithm>
#include <cmath>

namespace est::sim {
namespace {

float wrap_angle(float a) { return std::remainder(a, 6.28318530717958647692f); }

// The unicycle controller of the diff drive: turn towards the target, slow down while turning.
void unicycle_command(RouteFollower& f, const Pose2& p, float speed, float& v, float& w) {
  const Waypoint t = f.target(p.x, p.y);
  const float e = wrap_angle(std::atan2(t.y - p.y, t.x - p.x) - p.theta);
  w = std::clamp(2.5f * e, -1.5f, 1.5f);
  v = f.speed(speed) * std::max(0.1f, std::cos(e));
}

// World-frame velocity towards the target at `speed`.
void holonomic_command(RouteFollower& f, const Pose2& p, float speed, float& vx, float& vy) {
  const Waypoint t = f.target(p.x, p.y);
  const float dx = t.x - p.x, dy = t.y - p.y;
  const float d = std::max(1e-6f, std::hypot(dx, dy));
  vx = f.speed(speed) * dx / d;
  vy = f.speed(speed) * dy / d;
}

}  // namespace

BicycleRobot::BicycleRobot(const Route& route, const Pose2& start, std::size_t next_waypoint,
                           const BicycleParams& truth_noise, float speed, std::int32_t handle_detents)
    : follower_(route, next_waypoint, 0.5f), pose_(start), params_(truth_noise), speed_(speed),
      detents_(handle_detents) {}

BicycleControl BicycleRobot::step(Rng& rng) {
  const Waypoint t = follower_.target(pose_.x, pose_.y);
  const float limit = 0.9f * params_.steer_max;
  float a = std::clamp(wrap_angle(std::atan2(t.y - pose_.y, t.x - pose_.x) - pose_.theta), -limit, limit);
  if (detents_ >= 2) {  // the nearest detent, stop to stop
    const float step = 2.0f * params_.steer_max / static_cast<float>(detents_ - 1);
    a = -params_.steer_max + step * std::round((a + params_.steer_max) / step);
  }
  const BicycleControl u{follower_.speed(speed_) * (0.4f + 0.6f * std::cos(a)), a};
  pose_ = BicycleMotionModel::sample(pose_, u, params_, rng);
  return u;
}

void BicycleRobot::teleport(const Pose2& p, std::size_t next_waypoint) {
  pose_ = p;
  follower_.set_next(next_waypoint);
}

DiffDriveRobot::DiffDriveRobot(const Route& route, const Pose2& start, std::size_t next_waypoint,
                               const DiffDriveParams& truth_noise, float speed, float dt)
    : follower_(route, next_waypoint, 0.4f), pose_(start), params_(truth_noise), speed_(speed), dt_(dt) {}

DiffDriveControl DiffDriveRobot::step(Rng& rng) {
  float v = 0.0f, omega = 0.0f;
  unicycle_command(follower_, pose_, speed_, v, omega);
  const float half_track = 0.5f * params_.track_width;
  const float m_per_tick = diff_drive_m_per_tick(params_);
  const DiffDriveControl u{static_cast<std::int32_t>(std::lround((v - omega * half_track) * dt_ / m_per_tick)),
                           static_cast<std::int32_t>(std::lround((v + omega * half_track) * dt_ / m_per_tick))};
  pose_ = DiffDriveMotionModel::sample(pose_, u, params_, rng);
  return u;
}

void DiffDriveRobot::teleport(const Pose2& p, std::size_t next_waypoint) {
  pose_ = p;
  follower_.set_next(next_waypoint);
}

namespace {

class BicycleSim final : public SimRobot {
 public:
  BicycleSim(const Route& r, const Pose2& s, std::size_t next, const RobotTruth& t, float speed, float dt, double mpt)
      : robot_(r, s, next, t.bicycle, speed, t.handle_detents), dt_(dt), length_(t.bicycle.frame_length), mpt_(mpt) {}
  RobotStep step(Rng& rng) override {
    const BicycleControl u = robot_.step(rng);
    RobotStep out;
    out.wheels = 2;
    out.travel_ticks[0] = static_cast<double>(u.v) * static_cast<double>(dt_) / mpt_;
    out.travel_ticks[1] = out.travel_ticks[0] * std::cos(static_cast<double>(u.steer));  // the rear wheel
    out.steer_rad = u.steer;
    out.v1_mps = u.v;
    out.w_rps = u.v * std::sin(u.steer) / length_;
    return out;
  }
  const Pose2& pose() const override { return robot_.pose(); }
  void teleport(const Pose2& p, std::size_t next) override { robot_.teleport(p, next); }

 private:
  BicycleRobot robot_;
  float dt_, length_;
  double mpt_;
};

class DiffDriveSim final : public SimRobot {
 public:
  DiffDriveSim(const Route& r, const Pose2& s, std::size_t next, const RobotTruth& t, float speed, float dt)
      : robot_(r, s, next, t.diff_drive, speed, dt), params_(t.diff_drive), dt_(dt) {}
  RobotStep step(Rng& rng) override {
    const DiffDriveControl u = robot_.step(rng);
    const float m = diff_drive_m_per_tick(params_);
    RobotStep out;
    out.wheels = 2;
    out.travel_ticks[0] = static_cast<double>(u.left_ticks);
    out.travel_ticks[1] = static_cast<double>(u.right_ticks);
    const float l = static_cast<float>(u.left_ticks) * m, r = static_cast<float>(u.right_ticks) * m;
    out.v1_mps = 0.5f * (l + r) / dt_;
    out.w_rps = (r - l) / (params_.track_width * dt_);
    return out;
  }
  const Pose2& pose() const override { return robot_.pose(); }
  void teleport(const Pose2& p, std::size_t next) override { robot_.teleport(p, next); }

 private:
  DiffDriveRobot robot_;
  DiffDriveParams params_;
  float dt_;
};

// A robot that follows the route itself and keeps its own true pose.
class RoutedSim : public SimRobot {
 public:
  const Pose2& pose() const override { return pose_; }
  void teleport(const Pose2& p, std::size_t next) override {
    pose_ = p;
    follower_.set_next(next);
  }

 protected:
  RoutedSim(const Route& r, const Pose2& s, std::size_t next, float speed)
      : follower_(r, next, 0.4f), pose_(s), speed_(speed) {}
  RouteFollower follower_;
  Pose2 pose_;
  float speed_;
};

// The velocity model's robot: a unicycle commanded in (v, w), moving by the velocity model's own noise.
class VelocitySim final : public RoutedSim {
 public:
  VelocitySim(const Route& r, const Pose2& s, std::size_t next, const RobotTruth& t, float speed, float dt)
      : RoutedSim(r, s, next, speed), params_(t.velocity) {
    params_.dt = dt;
  }
  RobotStep step(Rng& rng) override {
    float v = 0.0f, w = 0.0f;
    unicycle_command(follower_, pose_, speed_, v, w);
    pose_ = VelocityMotionModel::sample(pose_, {v, w}, params_, rng);
    RobotStep out;
    out.v1_mps = v;
    out.w_rps = w;
    return out;
  }
 private:
  VelocityParams params_;
};

// The omnidirectional base: drives towards each waypoint in the world frame while its heading swings on its own
// (a slow sinusoid about the start heading), so it moves sideways and diagonally; four mecanum wheels.
class OmniSim final : public RoutedSim {
 public:
  OmniSim(const Route& r, const Pose2& s, std::size_t next, const RobotTruth& t, float speed, float dt, double mpt)
      : RoutedSim(r, s, next, speed), params_(t.omni), wheels_(t.omni_wheels), dt_(dt), heading0_(s.theta), mpt_(mpt) {
    params_.dt = dt;
  }
  RobotStep step(Rng& rng) override {
    float vx = 0.0f, vy = 0.0f;
    holonomic_command(follower_, pose_, speed_, vx, vy);
    time_ += dt_;
    const float want = heading0_ + 1.2f * std::sin(0.25f * time_);
    const float w = std::clamp(2.0f * wrap_angle(want - pose_.theta), -1.0f, 1.0f);
    const float c = std::cos(pose_.theta), s = std::sin(pose_.theta);
    const OmniControl u{c * vx + s * vy, -s * vx + c * vy, w};
    const Pose2 before = pose_;
    pose_ = OmniMotionModel::sample(pose_, u, params_, rng);
    // The wheels see the body's true displacement in its own frame.
    const float dx = pose_.x - before.x, dy = pose_.y - before.y;
    const float bx = c * dx + s * dy, by = -s * dx + c * dy, bt = wrap_angle(pose_.theta - before.theta);
    RobotStep out;
    out.wheels = wheels_.count;
    for (int i = 0; i < wheels_.count; ++i)
      out.travel_ticks[i] =
          static_cast<double>(wheels_.rows[i][0] * bx + wheels_.rows[i][1] * by + wheels_.rows[i][2] * bt) / mpt_;
    out.v1_mps = u.v1;
    out.v2_mps = u.v2;
    out.w_rps = u.w;
    return out;
  }
 private:
  OmniParams params_;
  OmniWheels wheels_;
  float dt_, heading0_, time_ = 0.0f;
  double mpt_;
};

// The holonomic point robot: x and y driven independently in its own frame, never turning (its heading is the
// start's for the whole run, whatever the route does).
class HolonomicSim final : public RoutedSim {
 public:
  HolonomicSim(const Route& r, const Pose2& s, std::size_t next, const RobotTruth& t, float speed, float dt)
      : RoutedSim(r, s, next, speed), params_(t.holonomic) {
    params_.point.B = Eigen::Matrix2f::Identity() * dt;
  }
  RobotStep step(Rng& rng) override {
    float vx = 0.0f, vy = 0.0f;
    holonomic_command(follower_, pose_, speed_, vx, vy);
    const float c = std::cos(pose_.theta), s = std::sin(pose_.theta);
    const Eigen::Vector2f u{c * vx + s * vy, -s * vx + c * vy};
    pose_ = HolonomicPoseMotionModel::sample(pose_, u, params_, rng);
    RobotStep out;
    out.v1_mps = u(0);
    out.v2_mps = u(1);
    return out;
  }
  const Pose2& pose() const override { return pose_; }
  void teleport(const Pose2& p, std::size_t next) override { RoutedSim::teleport({p.x, p.y, pose_.theta}, next); }

 private:
  HolonomicPoseParams params_;
};

}  // namespace

std::unique_ptr<SimRobot> make_robot(RobotKind kind, const Route& route, const Pose2& start, std::size_t next,
                                     const RobotTruth& truth, float speed, float dt, double metres_per_tick) {
  switch (kind) {
    case RobotKind::bicycle: return std::make_unique<BicycleSim>(route, start, next, truth, speed, dt, metres_per_tick);
    case RobotKind::diff_drive:
    case RobotKind::odometry:  // a differential-drive base that integrates its own odometry (the stream does)
      return std::make_unique<DiffDriveSim>(route, start, next, truth, speed, dt);
    case RobotKind::velocity: return std::make_unique<VelocitySim>(route, start, next, truth, speed, dt);
    case RobotKind::omni: return std::make_unique<OmniSim>(route, start, next, truth, speed, dt, metres_per_tick);
    case RobotKind::holonomic: return std::make_unique<HolonomicSim>(route, start, next, truth, speed, dt);
  }
  return nullptr;
}

}  // namespace est::sim
