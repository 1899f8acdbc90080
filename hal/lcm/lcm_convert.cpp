// LCM conversions of the estimator's own messages (hal/lcm/lcm_convert.hpp) and the reject names
// (hal/lcm/lcm_guard.hpp).
#include "hal/lcm/lcm_convert.hpp"

namespace hal::lcm {

const char* to_string(LcmReject r) {
  switch (r) {
    case LcmReject::none: return "none";
    case LcmReject::malformed: return "malformed";
    case LcmReject::bad_count: return "bad_count";
    case LcmReject::bad_shape: return "bad_shape";
    case LcmReject::bad_value: return "bad_value";
    case LcmReject::kCount: break;
  }
  return "unknown";
}

LcmReject to_hal(const est_lcm::team_message_t& m, TeamMessage& out, Fault& content) {
  content = Fault::none;
  if (m.num_measurements < 0 || static_cast<std::size_t>(m.num_measurements) > kMaxTeamMeasurements ||
      m.measurements.size() != static_cast<std::size_t>(m.num_measurements))
    return LcmReject::bad_count;
  out.stamp_ns = m.stamp_ns;
  out.robot_id = m.robot_id;
  out.v_mps = m.v_mps;
  out.omega_rps = m.omega_rps;
  out.dt_s = m.dt_s;
  out.count = m.measurements.size();
  for (std::size_t i = 0; i < out.count; ++i) {
    const est_lcm::team_measurement_t& z = m.measurements[i];
    if (z.type != est_lcm::team_measurement_t::LANDMARK && z.type != est_lcm::team_measurement_t::ROBOT)
      return LcmReject::bad_shape;
    out.measurements[i] = {z.type == est_lcm::team_measurement_t::ROBOT ? TeamTarget::robot : TeamTarget::landmark,
                           z.range_m, z.bearing_rad, z.target_id};
  }
  content = check_team_message(out);
  return content == Fault::none ? LcmReject::none : LcmReject::bad_value;
}

est_lcm::team_message_t to_lcm(const TeamMessage& t) {
  est_lcm::team_message_t m{};
  m.stamp_ns = t.stamp_ns;
  m.robot_id = t.robot_id;
  m.v_mps = t.v_mps;
  m.omega_rps = t.omega_rps;
  m.dt_s = t.dt_s;
  for (std::size_t i = 0; i < t.count && i < kMaxTeamMeasurements; ++i) {
    est_lcm::team_measurement_t z;
    z.type = t.measurements[i].type == TeamTarget::robot ? est_lcm::team_measurement_t::ROBOT
                                                          : est_lcm::team_measurement_t::LANDMARK;
    z.range_m = t.measurements[i].range_m;
    z.bearing_rad = t.measurements[i].bearing_rad;
    z.target_id = t.measurements[i].target_id;
    m.measurements.push_back(z);
  }
  m.num_measurements = static_cast<std::int16_t>(m.measurements.size());
  return m;
}

est_lcm::pose_estimate_t to_lcm(const Estimate& e) {
  est_lcm::pose_estimate_t m{};
  m.stamp_ns = e.stamp_ns;
  m.x_m = e.pose.x;
  m.y_m = e.pose.y;
  m.theta_rad = e.pose.theta;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) m.covariance[3 * r + c] = e.covariance(r, c);
  m.status = static_cast<std::int32_t>(e.status);
  m.rejected_inputs = static_cast<std::int32_t>(e.rejected_inputs > 0x7fffffffu ? 0x7fffffffu : e.rejected_inputs);
  return m;
}

Estimate to_hal(const est_lcm::pose_estimate_t& m) {
  Estimate e;
  e.stamp_ns = m.stamp_ns;
  e.pose = {m.x_m, m.y_m, m.theta_rad};
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) e.covariance(r, c) = m.covariance[3 * r + c];
  e.status = static_cast<std::uint32_t>(m.status);
  e.rejected_inputs = static_cast<std::uint32_t>(m.rejected_inputs < 0 ? 0 : m.rejected_inputs);
  return e;
}

}  // namespace hal::lcm
