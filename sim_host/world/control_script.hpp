#pragma once
// A control script: a robot driven by timed commands instead of a route. Each command is in the robot's motion
// model's own control terms (command_terms() names them per model), and is held from its time until the next
// command's; the last is held to the end of the run, and before the first the robot stands still.
#include <array>
#include <cstddef>
#include <string>
#include <vector>

#include "est/loop/model_kinds.hpp"

namespace est::sim {

// A command in the model's terms, unused terms zero:
//   bicycle              {v_mps, steer_rad}: the front wheel's speed and the steering angle
//   diff-drive, odometry {v_mps, w_rps}: the axle midpoint's speed and turn rate (the wheels' ticks follow)
//   velocity             {v_mps, w_rps}: the unicycle's twist
//   omni                 {v1_mps, v2_mps, w_rps}: forward, left and turn rate in the robot's frame
//   holonomic            {ux_mps, uy_mps}: forward and left in the robot's frame (it never turns)
using RobotCommand = std::array<float, 3>;

struct TimedCommand {
  double t_s = 0.0;  // from the start of the run
  RobotCommand u{};
};

// The number of terms of a model's command (2 or 3) and their names ("v_mps, steer_rad"), for files and messages.
int command_terms(est::loop::MotionModelKind model);
const char* command_term_names(est::loop::MotionModelKind model);

class ControlScript {
 public:
  // At least one command, times >= 0 and strictly increasing; throws std::invalid_argument otherwise.
  explicit ControlScript(std::vector<TimedCommand> commands);
  // The command in force at t_s.
  RobotCommand at(double t_s) const;
  const std::vector<TimedCommand>& commands() const { return commands_; }

 private:
  std::vector<TimedCommand> commands_;
};

}  // namespace est::sim
