#include "world/robots.hpp"

#include <algorithm>
#include <cmath>
#include <optional>

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

// The handlebar's nearest detent, stop to stop (with 2 or more detents; else the angle as it is).
float snap_steering(float a, const BicycleParams& params, std::int32_t detents) {
  if (detents < 2) return a;
  const float step = 2.0f * params.steer_max / static_cast<float>(detents - 1);
  return -params.steer_max + step * std::round((a + params.steer_max) / step);
}

// The bicycle's controller: points its front wheel at the target (steering clamped below the stop, then snapped to
// the handlebar's detents), slowing down in sharp turns.
BicycleControl bicycle_command(RouteFollower& f, const Pose2& p, const BicycleParams& params, float speed,
                               std::int32_t detents) {
  const Waypoint t = f.target(p.x, p.y);
  const float limit = 0.9f * params.steer_max;
  const float a = snap_steering(std::clamp(wrap_angle(std::atan2(t.y - p.y, t.x - p.x) - p.theta), -limit, limit),
                                params, detents);
  return {f.speed(speed) * (0.4f + 0.6f * std::cos(a)), a};
}

// A differential drive's twist (v, w) over one step as its wheels' travel in whole encoder ticks.
DiffDriveControl diff_drive_ticks(float v, float omega, const DiffDriveParams& p, float dt) {
  const float half_track = 0.5f * p.track_width;
  const float m_per_tick = diff_drive_m_per_tick(p);
  return {static_cast<std::int32_t>(std::lround((v - omega * half_track) * dt / m_per_tick)),
          static_cast<std::int32_t>(std::lround((v + omega * half_track) * dt / m_per_tick))};
}

}  // namespace

BicycleRobot::BicycleRobot(const Route& route, const Pose2& start, std::size_t next_waypoint,
                           const BicycleParams& truth_noise, float speed, std::int32_t handle_detents)
    : follower_(route, next_waypoint, 0.5f), pose_(start), params_(truth_noise), speed_(speed),
      detents_(handle_detents) {}

BicycleControl BicycleRobot::step(Rng& rng) {
  const BicycleControl u = bicycle_command(follower_, pose_, params_, speed_, detents_);
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
  const DiffDriveControl u = diff_drive_ticks(v, omega, params_, dt_);
  pose_ = DiffDriveMotionModel::sample(pose_, u, params_, rng);
  return u;
}

void DiffDriveRobot::teleport(const Pose2& p, std::size_t next_waypoint) {
  pose_ = p;
  follower_.set_next(next_waypoint);
}

namespace {

// A simulated robot and what drives it: its route (a follower towards the next waypoint) or its control script (the
// command in force at the step's start).
class DrivenSim : public SimRobot {
 public:
  RobotStep step(Rng& rng) override {
    RobotCommand u{};
    if (script_ != nullptr) u = script_->at(static_cast<double>(steps_) * static_cast<double>(dt_));
    ++steps_;
    return move(script_ != nullptr ? &u : nullptr, rng);
  }
  const Pose2& pose() const override { return pose_; }
  void teleport(const Pose2& p, std::size_t next) override {
    pose_ = p;
    if (follower_) follower_->set_next(next);
  }

 protected:
  // Exactly one of route and script.
  DrivenSim(const Route* route, const ControlScript* script, const Pose2& start, std::size_t next, float reach,
            float speed, float dt)
      : script_(script), pose_(start), speed_(speed), dt_(dt) {
    if (route != nullptr) follower_.emplace(*route, next, reach);
  }
  // One step under the script's command u, or the route's controller when u is null.
  virtual RobotStep move(const RobotCommand* u, Rng& rng) = 0;

  std::optional<RouteFollower> follower_;
  const ControlScript* script_;
  Pose2 pose_;
  float speed_, dt_;
  std::uint64_t steps_ = 0;
};

// Bicycle, pose at the front wheel: the route controller of BicycleRobot, or the script's (v, steer) on the
// handlebar's detents.
class BicycleSim final : public DrivenSim {
 public:
  BicycleSim(const Route* r, const ControlScript* script, const Pose2& s, std::size_t next, const RobotTruth& t,
             float speed, float dt, double mpt)
      : DrivenSim(r, script, s, next, 0.5f, speed, dt), params_(t.bicycle), detents_(t.handle_detents), mpt_(mpt) {}
  RobotStep move(const RobotCommand* c, Rng& rng) override {
    const BicycleControl u = c != nullptr ? BicycleControl{(*c)[0], snap_steering((*c)[1], params_, detents_)}
                                          : bicycle_command(*follower_, pose_, params_, speed_, detents_);
    pose_ = BicycleMotionModel::sample(pose_, u, params_, rng);
    RobotStep out;
    out.wheels = 2;
    out.travel_ticks[0] = static_cast<double>(u.v) * static_cast<double>(dt_) / mpt_;
    out.travel_ticks[1] = out.travel_ticks[0] * std::cos(static_cast<double>(u.steer));  // the rear wheel
    out.steer_rad = u.steer;
    out.v1_mps = u.v;
    out.w_rps = u.v * std::sin(u.steer) / params_.frame_length;
    return out;
  }

 private:
  BicycleParams params_;
  std::int32_t detents_;
  double mpt_;
};

// Differential drive, pose at the axle midpoint: the unicycle controller's or the script's (v, w), as whole ticks.
class DiffDriveSim final : public DrivenSim {
 public:
  DiffDriveSim(const Route* r, const ControlScript* script, const Pose2& s, std::size_t next, const RobotTruth& t,
               float speed, float dt)
      : DrivenSim(r, script, s, next, 0.4f, speed, dt), params_(t.diff_drive) {}
  RobotStep move(const RobotCommand* c, Rng& rng) override {
    float v = 0.0f, omega = 0.0f;
    if (c != nullptr) v = (*c)[0], omega = (*c)[1];
    else unicycle_command(*follower_, pose_, speed_, v, omega);
    const DiffDriveControl u = diff_drive_ticks(v, omega, params_, dt_);
    pose_ = DiffDriveMotionModel::sample(pose_, u, params_, rng);
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

 private:
  DiffDriveParams params_;
};

// The velocity model's robot: a unicycle commanded in (v, w), moving by the velocity model's own noise.
class VelocitySim final : public DrivenSim {
 public:
  VelocitySim(const Route* r, const ControlScript* script, const Pose2& s, std::size_t next, const RobotTruth& t,
              float speed, float dt)
      : DrivenSim(r, script, s, next, 0.4f, speed, dt), params_(t.velocity) {
    params_.dt = dt;
  }
  RobotStep move(const RobotCommand* c, Rng& rng) override {
    float v = 0.0f, w = 0.0f;
    if (c != nullptr) v = (*c)[0], w = (*c)[1];
    else unicycle_command(*follower_, pose_, speed_, v, w);
    pose_ = VelocityMotionModel::sample(pose_, {v, w}, params_, rng);
    RobotStep out;
    out.v1_mps = v;
    out.w_rps = w;
    return out;
  }
 private:
  VelocityParams params_;
};

// The omnidirectional base: on a route it drives towards each waypoint in the world frame while its heading swings
// on its own (a slow sinusoid about the start heading), so it moves sideways and diagonally; on a script it takes
// (v1, v2, w) in its own frame. Four mecanum wheels.
class OmniSim final : public DrivenSim {
 public:
  OmniSim(const Route* r, const ControlScript* script, const Pose2& s, std::size_t next, const RobotTruth& t,
          float speed, float dt, double mpt)
      : DrivenSim(r, script, s, next, 0.4f, speed, dt), params_(t.omni), wheels_(t.omni_wheels),
        heading0_(s.theta), mpt_(mpt) {
    params_.dt = dt;
  }
  RobotStep move(const RobotCommand* command, Rng& rng) override {
    const float c = std::cos(pose_.theta), s = std::sin(pose_.theta);
    OmniControl u{};
    if (command != nullptr) {
      u = {(*command)[0], (*command)[1], (*command)[2]};
    } else {
      float vx = 0.0f, vy = 0.0f;
      holonomic_command(*follower_, pose_, speed_, vx, vy);
      time_ += dt_;
      const float want = heading0_ + 1.2f * std::sin(0.25f * time_);
      const float w = std::clamp(2.0f * wrap_angle(want - pose_.theta), -1.0f, 1.0f);
      u = {c * vx + s * vy, -s * vx + c * vy, w};
    }
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
  float heading0_, time_ = 0.0f;
  double mpt_;
};

// The holonomic point robot: x and y driven independently in its own frame, never turning (its heading is the
// start's for the whole run, whatever the route does); on a script it takes (u_x, u_y) in its own frame.
class HolonomicSim final : public DrivenSim {
 public:
  HolonomicSim(const Route* r, const ControlScript* script, const Pose2& s, std::size_t next, const RobotTruth& t,
               float speed, float dt)
      : DrivenSim(r, script, s, next, 0.4f, speed, dt), params_(t.holonomic) {
    params_.point.B = Eigen::Matrix2f::Identity() * dt;
  }
  RobotStep move(const RobotCommand* command, Rng& rng) override {
    Eigen::Vector2f u;
    if (command != nullptr) {
      u = {(*command)[0], (*command)[1]};
    } else {
      float vx = 0.0f, vy = 0.0f;
      holonomic_command(*follower_, pose_, speed_, vx, vy);
      const float c = std::cos(pose_.theta), s = std::sin(pose_.theta);
      u = {c * vx + s * vy, -s * vx + c * vy};
    }
    pose_ = HolonomicPoseMotionModel::sample(pose_, u, params_, rng);
    RobotStep out;
    out.v1_mps = u(0);
    out.v2_mps = u(1);
    return out;
  }
  void teleport(const Pose2& p, std::size_t next) override { DrivenSim::teleport({p.x, p.y, pose_.theta}, next); }

 private:
  HolonomicPoseParams params_;
};

std::unique_ptr<SimRobot> make(RobotKind kind, const Route* route, const ControlScript* script, const Pose2& start,
                               std::size_t next, const RobotTruth& truth, float speed, float dt, double mpt) {
  switch (kind) {
    case RobotKind::bicycle: return std::make_unique<BicycleSim>(route, script, start, next, truth, speed, dt, mpt);
    case RobotKind::diff_drive:
    case RobotKind::odometry:  // a differential-drive base that integrates its own odometry (the stream does)
      return std::make_unique<DiffDriveSim>(route, script, start, next, truth, speed, dt);
    case RobotKind::velocity: return std::make_unique<VelocitySim>(route, script, start, next, truth, speed, dt);
    case RobotKind::omni: return std::make_unique<OmniSim>(route, script, start, next, truth, speed, dt, mpt);
    case RobotKind::holonomic: return std::make_unique<HolonomicSim>(route, script, start, next, truth, speed, dt);
  }
  return nullptr;
}

}  // namespace

std::unique_ptr<SimRobot> make_robot(RobotKind kind, const Route& route, const Pose2& start, std::size_t next,
                                     const RobotTruth& truth, float speed, float dt, double metres_per_tick) {
  return make(kind, &route, nullptr, start, next, truth, speed, dt, metres_per_tick);
}

std::unique_ptr<SimRobot> make_robot(RobotKind kind, const ControlScript& script, const Pose2& start,
                                     const RobotTruth& truth, float dt, double metres_per_tick) {
  return make(kind, nullptr, &script, start, 0, truth, 0.0f, dt, metres_per_tick);
}

}  // namespace est::sim
