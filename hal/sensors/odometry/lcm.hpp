#pragma once
// The odometry pose on LCM: est_lcm::odometry_t (floats: the position does not wrap).
#include <cstdint>
#include <est_lcm/odometry_t.hpp>

#include "hal/lcm/channels.hpp"
#include "hal/lcm/lcm_guard.hpp"
#include "hal/sensors/odometry/odometry.hpp"

namespace hal::lcm {

inline OdometrySample to_hal(const est_lcm::odometry_t& m) {
  OdometrySample s;
  s.stamp_ns = m.stamp_ns;
  s.pose = {m.x_m, m.y_m, m.theta_rad};
  return s;
}
inline est_lcm::odometry_t to_lcm(const OdometrySample& s) {
  est_lcm::odometry_t m{};
  m.stamp_ns = s.stamp_ns;
  m.x_m = s.pose.x;
  m.y_m = s.pose.y;
  m.theta_rad = s.pose.theta;
  return m;
}

template <>
struct LcmCodec<OdometrySample> {
  using Message = est_lcm::odometry_t;
  static constexpr std::string Channels::*channel = &Channels::odometry;
  struct Storage {};
  static std::int64_t max_count(const InputConfig&) { return 0; }
  static LcmReject to_hal(const Message& m, const InputConfig&, Storage&, OdometrySample& out) {
    out = lcm::to_hal(m);
    return LcmReject::none;
  }
};

}  // namespace hal::lcm
