#pragma once
// Simulated robots that drive a route. Each step picks the command a simple controller gives towards the route's
// next waypoint, then moves the true pose by drawing from the robot's motion model with the TRUE noise parameters
// (so the truth is a sample of the very process the filter models, with noise the filter is told is larger).
// What the filter receives is the command (bicycle) or the encoder ticks (differential drive).
#include "est/geometry/pose2.hpp"
#include "est/motion/bicycle_model.hpp"
#include "est/motion/diff_drive_model.hpp"
#include "est/random/xoshiro128.hpp"
#include "world/route.hpp"

namespace est::sim {

// Bicycle, pose at the front wheel; points its front wheel at the target (steering clamped below the stop) and
// slows down in sharp turns.
class BicycleRobot {
 public:
  BicycleRobot(const Route& route, const Pose2& start, std::size_t next_waypoint, const BicycleParams& truth_noise,
               float speed);
  BicycleControl step(Rng& rng);
  const Pose2& pose() const { return pose_; }
  // Kidnapping: the robot is carried elsewhere without telling anyone.
  void teleport(const Pose2& p, std::size_t next_waypoint);
  const BicycleParams& params() const { return params_; }
  std::size_t laps() const { return follower_.laps(); }

 private:
  RouteFollower follower_;
  Pose2 pose_;
  BicycleParams params_;
  float speed_;
};

// Differential drive, pose at the axle midpoint; turns towards the target at a rate proportional to the heading
// error; wheel travel is quantized to encoder ticks, which is what it reports.
class DiffDriveRobot {
 public:
  DiffDriveRobot(const Route& route, const Pose2& start, std::size_t next_waypoint, const DiffDriveParams& truth_noise,
                 float speed, float dt);
  DiffDriveControl step(Rng& rng);
  const Pose2& pose() const { return pose_; }
  void teleport(const Pose2& p, std::size_t next_waypoint);
  const DiffDriveParams& params() const { return params_; }
  std::size_t laps() const { return follower_.laps(); }

 private:
  RouteFollower follower_;
  Pose2 pose_;
  DiffDriveParams params_;
  float speed_;
  float dt_;
};

}  // namespace est::sim
