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
