#pragma once
// The team message on LCM: est_lcm::team_message_t on one channel for the whole team (Channels::team), the sender in
// the message. Lossless both ways, bit for bit: the floats copied, seq as the bits of an int32, the control kind, the
// target kinds and the wheel count as their bytes, so the validator (hal/team/validator.hpp) judges exactly what the
// sender wrote, unknown kinds included. Host only.
#include <cstddef>
#include <cstdint>
#include <est_lcm/team_message_t.hpp>

#include "est/team/team_message.hpp"
#include "hal/lcm/lcm_guard.hpp"

namespace hal::lcm {

template <> struct LeadingCount<est_lcm::team_message_t> { static constexpr int bytes = 2; };

// bad_count: num_measurements negative, above est::team::kMaxTeamMeasurements or not the array's length; bad_shape:
// a has_bearing byte other than 0 and 1. On a refusal `out` is partly written.
inline LcmReject to_hal(const est_lcm::team_message_t& m, est::team::TeamMessage& out) {
  using namespace est::team;
  if (m.num_measurements < 0 || m.num_measurements > kMaxTeamMeasurements ||
      m.measurements.size() != static_cast<std::size_t>(m.num_measurements))
    return LcmReject::bad_count;
  out.robot = m.robot_id;
  out.seq = static_cast<std::uint32_t>(m.seq);
  out.stamp_ns = m.stamp_ns;
  out.control.kind = static_cast<ControlKind>(static_cast<std::uint8_t>(m.control_kind));
  out.control.dt_s = m.dt_s;
  out.control.v1 = m.v1;
  out.control.v2 = m.v2;
  out.control.w = m.w;
  for (int i = 0; i < est::loop::kMaxWheels; ++i) out.control.ticks[i] = m.ticks[i];
  out.control.wheel_count = static_cast<std::uint8_t>(m.wheel_count);
  out.control.steering_rad = m.steering_rad;
  out.count = m.num_measurements;
  for (std::int32_t i = 0; i < out.count; ++i) {
    const est_lcm::team_measurement_t& z = m.measurements[static_cast<std::size_t>(i)];
    if (z.has_bearing != 0 && z.has_bearing != 1) return LcmReject::bad_shape;
    out.measurements[i] = {static_cast<TargetKind>(static_cast<std::uint8_t>(z.target)), z.has_bearing == 1,
                           z.range_m, z.bearing_rad, z.id};
  }
  return LcmReject::none;
}

// A count outside 0..kMaxTeamMeasurements is sent clamped to it.
inline est_lcm::team_message_t to_lcm(const est::team::TeamMessage& t) {
  using namespace est::team;
  est_lcm::team_message_t m{};
  m.robot_id = t.robot;
  m.seq = static_cast<std::int32_t>(t.seq);
  m.stamp_ns = t.stamp_ns;
  m.control_kind = static_cast<std::int8_t>(static_cast<std::uint8_t>(t.control.kind));
  m.dt_s = t.control.dt_s;
  m.v1 = t.control.v1;
  m.v2 = t.control.v2;
  m.w = t.control.w;
  for (int i = 0; i < est::loop::kMaxWheels; ++i) m.ticks[i] = t.control.ticks[i];
  m.wheel_count = static_cast<std::int8_t>(t.control.wheel_count);
  m.steering_rad = t.control.steering_rad;
  const std::int32_t n = t.count < 0 ? 0 : t.count > kMaxTeamMeasurements ? kMaxTeamMeasurements : t.count;
  m.measurements.resize(static_cast<std::size_t>(n));
  for (std::int32_t i = 0; i < n; ++i) {
    const TeamMeasurement& z = t.measurements[i];
    est_lcm::team_measurement_t& o = m.measurements[static_cast<std::size_t>(i)];
    o.target = static_cast<std::int8_t>(static_cast<std::uint8_t>(z.target));
    o.has_bearing = z.has_bearing ? 1 : 0;
    o.range_m = z.range_m;
    o.bearing_rad = z.bearing_rad;
    o.id = z.id;
  }
  m.num_measurements = static_cast<std::int16_t>(n);
  return m;
}

}  // namespace hal::lcm
