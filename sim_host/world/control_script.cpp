#include "world/control_script.hpp"

#include <algorithm>
#include <stdexcept>

namespace est::sim {

using est::loop::MotionModelKind;

int command_terms(MotionModelKind model) { return model == MotionModelKind::omni ? 3 : 2; }

const char* command_term_names(MotionModelKind model) {
  switch (model) {
    case MotionModelKind::bicycle: return "v_mps, steer_rad";
    case MotionModelKind::diff_drive:
    case MotionModelKind::odometry:
    case MotionModelKind::velocity: return "v_mps, w_rps";
    case MotionModelKind::omni: return "v1_mps, v2_mps, w_rps";
    case MotionModelKind::holonomic: return "ux_mps, uy_mps";
  }
  return "?";
}

ControlScript::ControlScript(std::vector<TimedCommand> commands) : commands_(std::move(commands)) {
  if (commands_.empty()) throw std::invalid_argument("a control script needs at least one command");
  for (std::size_t i = 0; i < commands_.size(); ++i)
    if (!(commands_[i].t_s >= 0.0) || (i > 0 && !(commands_[i].t_s > commands_[i - 1].t_s)))
      throw std::invalid_argument("a control script's times must be >= 0 and increasing");
}

RobotCommand ControlScript::at(double t_s) const {
  // The last command whose time has come.
  const auto after = std::upper_bound(commands_.begin(), commands_.end(), t_s,
                                      [](double t, const TimedCommand& c) { return t < c.t_s; });
  return after == commands_.begin() ? RobotCommand{} : std::prev(after)->u;
}

}  // namespace est::sim
