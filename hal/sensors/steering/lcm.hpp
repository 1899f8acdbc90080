#pragma once
// The steering angle on LCM: est_lcm::steering_t.
#include <cstdint>
#include <est_lcm/steering_t.hpp>

#include "hal/lcm/channels.hpp"
#include "hal/lcm/lcm_guard.hpp"
#include "hal/sensors/steering/steering.hpp"

namespace hal::lcm {

inline SteeringSample to_hal(const est_lcm::steering_t& m) { return {m.stamp_ns, m.angle_rad}; }
inline est_lcm::steering_t to_lcm(const SteeringSample& s) {
  est_lcm::steering_t m{};
  m.stamp_ns = s.stamp_ns;
  m.angle_rad = s.angle_rad;
  return m;
}

template <>
struct LcmCodec<SteeringSample> {
  using Message = est_lcm::steering_t;
  static constexpr std::string Channels::*channel = &Channels::steering;
  struct Storage {};
  static std::int64_t max_count(const InputConfig&) { return 0; }
  static LcmReject to_hal(const Message& m, const InputConfig&, Storage&, SteeringSample& out) {
    out = lcm::to_hal(m);
    return LcmReject::none;
  }
};

}  // namespace hal::lcm
