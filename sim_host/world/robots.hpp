#pragma once
// Simulated robots that drive a route or a control script (world/control_script.hpp). Each step picks the command a
// simple controller gives towards the route's next waypoint, or the script's command in force, then moves the true pose by drawing from the robot's motion model with the TRUE noise parameters
// (so the truth is a sample of the very process the filter models, with noise the filter is told is larger).
// BicycleRobot and DiffDriveRobot report their commands; SimRobot (below) is every model behind one interface, with
// what its sensors would see of each step (wheel travel, steering, the commanded twist).
#include <cstddef>
#include <cstdint>
#include <memory>

#include "est/geometry/pose2.hpp"
#include "est/loop/model_kinds.hpp"
#include "est/motion/bicycle_model.hpp"
#include "est/motion/diff_drive_model.hpp"
#include "est/motion/holonomic_pose_model.hpp"
#include "est/motion/omni_model.hpp"
#include "est/motion/omni_wheels.hpp"
#include "est/motion/velocity_model.hpp"
#include "est/random/xoshiro128.hpp"
#include "world/control_script.hpp"
#include "world/route.hpp"

namespace est::sim {

// Bicycle, pose at the front wheel; points its front wheel at the target (steering clamped below the stop) and
// slows down in sharp turns.
class BicycleRobot {
 public:
  BicycleRobot(const Route& route, const Pose2& start, std::size_t next_waypoint, const BicycleParams& truth_noise,
               float speed, std::int32_t handle_detents = 0);
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
  std::int32_t detents_;
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

// The six robots of the simulator, one per motion model.
using RobotKind = est::loop::MotionModelKind;

// What one step did, as the robot's own sensors would measure it before their errors: each wheel's true travel in
// encoder ticks (fractional; the bicycle's wheel 0 is the front wheel, 1 the rear; the diff drive's and the odometry
// base's 0 left, 1 right; the omni base's four mecanum wheels), the steering angle (bicycle) and the commanded body
// twist (v1 forward, v2 left, w; the velocity and holonomic robots' controls).
struct RobotStep {
  std::uint8_t wheels = 0;
  double travel_ticks[4] = {};
  float steer_rad = 0.0f;
  float v1_mps = 0.0f, v2_mps = 0.0f, w_rps = 0.0f;
};

// True noise of every robot, per 10 ms step.
struct RobotTruth {
  BicycleParams bicycle;
  DiffDriveParams diff_drive;
  VelocityParams velocity;
  OmniParams omni;
  HolonomicPoseParams holonomic;
  OmniWheels omni_wheels;  // the omni base's mecanum wheels (wheel travel from body motion)
  // A bicycle whose handlebar has this many detents from stop to stop (the exercise's handlebar positions: the
  // steering snaps to the nearest); 0: a continuous handlebar.
  std::int32_t handle_detents = 0;
};

class SimRobot {
 public:
  virtual ~SimRobot() = default;
  virtual RobotStep step(Rng& rng) = 0;
  virtual const Pose2& pose() const = 0;
  // Kidnapping: the robot is carried elsewhere without telling anyone (a robot that never turns keeps its heading).
  virtual void teleport(const Pose2& p, std::size_t next_waypoint) = 0;
};

// `dt`: the step (s); the route, its start pose and the first waypoint to head for; the cruise speed; the encoders'
// travel per tick (m).
std::unique_ptr<SimRobot> make_robot(RobotKind kind, const Route& route, const Pose2& start, std::size_t next_waypoint,
                                     const RobotTruth& truth, float speed, float dt, double metres_per_tick);
// A robot driven by `script` (kept by the caller) from `start`: step k takes the command in force at k dt, in the
// model's terms (control_script.hpp); the bicycle's steering snaps to the handlebar's detents as on a route.
std::unique_ptr<SimRobot> make_robot(RobotKind kind, const ControlScript& script, const Pose2& start,
                                     const RobotTruth& truth, float dt, double metres_per_tick);

}  // namespace est::sim
