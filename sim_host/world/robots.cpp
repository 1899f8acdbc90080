#include "world/robots.hpp"

#include <algorithm>
#include <cmath>

namespace est::sim {
namespace {

float wrap(float a) { return std::remainder(a, 6.28318530717958647692f); }

}  // namespace

BicycleRobot::BicycleRobot(const Route& route, const Pose2& start, std::size_t next_waypoint,
                           const BicycleParams& truth_noise, float speed)
    : follower_(route, next_waypoint, 0.5f), pose_(start), params_(truth_noise), speed_(speed) {}

BicycleControl BicycleRobot::step(Rng& rng) {
  const Waypoint t = follower_.target(pose_.x, pose_.y);
  const float limit = 0.9f * params_.steer_max;
  const float a = std::clamp(wrap(std::atan2(t.y - pose_.y, t.x - pose_.x) - pose_.theta), -limit, limit);
  const BicycleControl u{speed_ * (0.4f + 0.6f * std::cos(a)), a};
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
  const Waypoint t = follower_.target(pose_.x, pose_.y);
  const float e = wrap(std::atan2(t.y - pose_.y, t.x - pose_.x) - pose_.theta);
  const float omega = std::clamp(2.5f * e, -1.5f, 1.5f);
  const float v = speed_ * std::max(0.1f, std::cos(e));
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

}  // namespace est::sim
