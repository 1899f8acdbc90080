#pragma once
// Wheel encoders on LCM: est_lcm::encoder_ticks_t, raw counters of counter_bits (32 by default) per wheel.
#include <cstdint>
#include <est_lcm/encoder_ticks_t.hpp>

#include "hal/lcm/channels.hpp"
#include "hal/lcm/lcm_guard.hpp"
#include "hal/sensors/wheel_ticks/wheel_ticks.hpp"

namespace hal::lcm {

template <> struct LeadingCount<est_lcm::encoder_ticks_t> { static constexpr int bytes = 2; };

LcmReject to_hal(const est_lcm::encoder_ticks_t& m, unsigned expected_counter_bits, WheelTicks& out);
est_lcm::encoder_ticks_t to_lcm(const WheelTicks& s, unsigned counter_bits);

template <>
struct LcmCodec<WheelTicks> {
  using Message = est_lcm::encoder_ticks_t;
  static constexpr std::string Channels::*channel = &Channels::wheel_ticks;
  struct Storage {};
  static std::int64_t max_count(const InputConfig&) { return static_cast<std::int64_t>(kMaxWheels); }
  static LcmReject to_hal(const Message& m, const InputConfig& c, Storage&, WheelTicks& out) {
    return lcm::to_hal(m, c.wheel_counter_bits, out);
  }
};

}  // namespace hal::lcm
