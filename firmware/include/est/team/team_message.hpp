#pragma once
// The team's shared message, in firmware types: one robot's control over one step and its measurements at the
// step's end (Probabilistic Robotics' cooperative EKF-SLAM exercise: the robots share z_k and u_k at every step).
// Step k of every robot covers (t0 + (k - 1) T, t0 + k T]; `seq` is k. The HAL validates what arrives
// (hal/team/) and the team loop (est/team/team_window.hpp) orders it by (seq, robot), so the estimate does not depend
// on the order of arrival.
//
// The control carries what any motion model takes: wheel ticks (with the steering angle of a bicycle), (v, w) of the
// velocity model, (v1, v2, w) of the omnidirectional base, (u_x, u_y) of the holonomic point robot (the exercise's
// u = [u_x, u_y], here a velocity held over dt: the displacement is u dt). A measurement is a range, or a range and
// a bearing (in the sender's frame, counter-clockwise; the world frame for a point robot, which has no heading), to a
// landmark or to a robot, with the target's identity or without it (id = kAnonymous: the sensor sees a robot but
// not which one, the correspondence problem of the three-robot exercise).
#include <cstdint>

#include "est/loop/inputs.hpp"

namespace est::team {

using TimeNs = est::loop::TimeNs;

inline constexpr std::int32_t kMaxTeamRobots = 8;           // robots a team message may name (ids 0..7)
inline constexpr std::int32_t kMaxTeamMeasurements = 32;    // measurements per message
inline constexpr std::int32_t kAnonymous = -1;              // a target seen without its identity

enum class ControlKind : std::uint8_t {
  none = 0,         // no control this step (the robot is predicted with its unknown-control noise)
  wheel_ticks = 1,  // ticks[0..wheel_count) over the step, steering_rad held (bicycle)
  velocity = 2,     // (v, w) = (v1, w)
  omni = 3,         // (v1, v2, w)
  holonomic = 4,    // (u_x, u_y) = (v1, v2), world frame
};
inline constexpr std::uint8_t kControlKindCount = 5;

struct TeamControl {
  ControlKind kind = ControlKind::none;
  float dt_s = 0.0f;  // the step the control is held over
  float v1 = 0.0f;    // m/s: forward (velocity, omni) or u_x (holonomic)
  float v2 = 0.0f;    // m/s: leftward (omni) or u_y (holonomic)
  float w = 0.0f;     // rad/s
  std::int32_t ticks[est::loop::kMaxWheels] = {};
  std::uint8_t wheel_count = 0;
  float steering_rad = 0.0f;
};

enum class TargetKind : std::uint8_t { landmark = 0, robot = 1 };

struct TeamMeasurement {
  TargetKind target = TargetKind::landmark;
  bool has_bearing = false;
  float range_m = 0.0f;
  float bearing_rad = 0.0f;          // when has_bearing
  std::int32_t id = kAnonymous;      // landmark id or robot id; kAnonymous when the sensor cannot tell
};

struct TeamMessage {
  std::int32_t robot = 0;            // the sender, 0..kMaxTeamRobots-1
  std::uint32_t seq = 0;             // the step k
  TimeNs stamp_ns = 0;               // the step's end on the sender's clock
  TeamControl control;
  std::int32_t count = 0;            // measurements[0..count)
  TeamMeasurement measurements[kMaxTeamMeasurements] = {};
};

// Why a team message was refused; the HAL counts each (hal/team/validator.hpp) and the team window counts the
// ones only it can tell (late, capacity).
enum class TeamReject : std::uint8_t {
  none = 0,
  malformed,       // a non-finite or out-of-range field, a count over the capacity, an unknown control kind
  unknown_robot,   // sender or named robot outside the team
  duplicate,       // (robot, seq) already received
  out_of_order,    // older than the sender's newest (accepted, reordered by the window; counted)
  late,            // its step was already closed by the window
  capacity,        // more open steps than the window holds
};
inline constexpr std::uint8_t kTeamRejectCount = 7;

inline const char* to_string(TeamReject r) {
  switch (r) {
    case TeamReject::none: return "none";
    case TeamReject::malformed: return "malformed";
    case TeamReject::unknown_robot: return "unknown_robot";
    case TeamReject::duplicate: return "duplicate";
    case TeamReject::out_of_order: return "out_of_order";
    case TeamReject::late: return "late";
    case TeamReject::capacity: return "capacity";
  }
  return "?";
}

// Content checks of one message for a team of `robots` (structure only; the sequence is the window's): finite
// fields, ranges >= 0, |bearing| <= pi, 0 < dt <= 1 s when there is a control, wheel_count <= kMaxWheels, count
// within the capacity, every named robot in the team and never the sender itself.
inline TeamReject check(const TeamMessage& m, std::int32_t robots) {
  auto finite = [](float x) { return x - x == 0.0f; };
  if (m.robot < 0 || m.robot >= robots || robots > kMaxTeamRobots) return TeamReject::unknown_robot;
  if (m.count < 0 || m.count > kMaxTeamMeasurements) return TeamReject::malformed;
  const TeamControl& u = m.control;
  if (static_cast<std::uint8_t>(u.kind) >= kControlKindCount) return TeamReject::malformed;
  if (!finite(u.dt_s) || !finite(u.v1) || !finite(u.v2) || !finite(u.w) || !finite(u.steering_rad))
    return TeamReject::malformed;
  if (u.kind != ControlKind::none && !(u.dt_s > 0.0f && u.dt_s <= 1.0f)) return TeamReject::malformed;
  if (u.wheel_count > est::loop::kMaxWheels) return TeamReject::malformed;
  for (std::int32_t i = 0; i < m.count; ++i) {
    const TeamMeasurement& z = m.measurements[i];
    if (static_cast<std::uint8_t>(z.target) > 1u) return TeamReject::malformed;
    if (!finite(z.range_m) || !(z.range_m >= 0.0f)) return TeamReject::malformed;
    if (z.has_bearing && (!finite(z.bearing_rad) || z.bearing_rad > 3.14159274f || z.bearing_rad < -3.14159274f))
      return TeamReject::malformed;
    if (z.target == TargetKind::robot && z.id != kAnonymous && (z.id < 0 || z.id >= robots || z.id == m.robot))
      return TeamReject::unknown_robot;
  }
  return TeamReject::none;
}

}  // namespace est::team
