#pragma once
// The team message in the HAL: the firmware's own type (est/team/team_message.hpp) and the port the accepted ones
// arrive at. A backend decodes a teammate's message, the team validator (hal/team/validator.hpp) judges it, and what
// it accepts, in order or not, reaches the TeamPort; the team window behind the port orders it by (seq, robot).
#include "est/team/team_message.hpp"

namespace hal {

class TeamPort {
 public:
  // The message is valid only during the call: copy what you keep.
  virtual void on_team_message(const est::team::TeamMessage& message) = 0;

 protected:
  // Not virtual: a deleting destructor would reference operator delete on the board.
  ~TeamPort() = default;
};

}  // namespace hal
