#pragma once
// The twist on LCM: est_lcm::twist_t.
#include <cstdint>
#include <est_lcm/twist_t.hpp>

#include "hal/lcm/channels.hpp"
#include "hal/lcm/lcm_guard.hpp"
#include "hal/sensors/twist/twist.hpp"

namespace hal::lcm {

inline TwistSample to_hal(const est_lcm::twist_t& m) { return {m.stamp_ns, m.v1_mps, m.v2_mps, m.w_rps}; }
inline est_lcm::twist_t to_lcm(const TwistSample& s) {
  est_lcm::twist_t m{};
  m.stamp_ns = s.stamp_ns;
  m.v1_mps = s.v1_mps;
  m.v2_mps = s.v2_mps;
  m.w_rps = s.w_rps;
  return m;
}

template <>
struct LcmCodec<TwistSample> {
  using Message = est_lcm::twist_t;
  static constexpr std::string Channels::*channel = &Channels::twist;
  struct Storage {};
  static std::int64_t max_count(const InputConfig&) { return 0; }
  static LcmReject to_hal(const Message& m, const InputConfig&, Storage&, TwistSample& out) {
    out = lcm::to_hal(m);
    return LcmReject::none;
  }
};

}  // namespace hal::lcm
