#pragma once
// Wheel encoder samples: the raw hardware counters of up to four wheels as read, and the unwrapped tick increments
// the loop uses (est::loop::WheelTicksInput). Which wheel is which is the robot's: wheels 0 and 1 are left and right
// of a differential drive; wheel 0 is the bicycle's traction wheel; an omnidirectional base numbers its three or
// four wheels as its kinematics does (est/motion/omni_wheels.hpp).
#include <cstddef>
#include <cstdint>

#include "est/loop/inputs.hpp"
#include "hal/time.hpp"

namespace hal {

inline constexpr std::size_t kMaxWheels = static_cast<std::size_t>(est::loop::kMaxWheels);

// Raw counters of an up/down hardware counter `counter_bits` wide (e.g. a 16-bit timer in encoder mode): they wrap.
struct WheelTicks {
  TimeNs stamp_ns = 0;
  std::uint8_t wheel_count = 0;
  std::uint32_t count[kMaxWheels] = {};
};

// Signed ticks per wheel since the previous accepted sample, over dt_ns (0 for the first sample).
struct WheelTickDelta {
  TimeNs stamp_ns = 0;
  TimeNs dt_ns = 0;
  std::uint8_t wheel_count = 0;
  std::int32_t ticks[kMaxWheels] = {};
};

// Mask of a counter `bits` wide, 1 <= bits <= 32.
constexpr std::uint32_t counter_mask(unsigned bits) {
  return bits >= 32u ? 0xffffffffu : (std::uint32_t{1} << bits) - 1u;
}

// Shortest signed distance from `before` to `now` on a counter `bits` wide: exact while the wheel moved less than
// half the counter's range between two samples (the validator's rate limit makes sure of it).
constexpr std::int32_t counter_delta(std::uint32_t now, std::uint32_t before, unsigned bits) {
  const std::uint32_t mask = counter_mask(bits);
  const std::uint32_t d = (now - before) & mask;
  const std::uint32_t half = (mask >> 1) + 1u;
  if (d < half) return static_cast<std::int32_t>(d);
  return static_cast<std::int32_t>(static_cast<std::int64_t>(d) - static_cast<std::int64_t>(mask) - 1);
}

// The loop's input (the wall between the HAL and the firmware: converted here, once).
template <typename Push>
void to_loop_inputs(const WheelTickDelta& d, Push&& push) {
  est::loop::WheelTicksInput in;
  in.t_ns = d.stamp_ns;
  in.wheel_count = d.wheel_count;
  for (std::size_t w = 0; w < kMaxWheels; ++w) in.ticks[w] = d.ticks[w];
  push(in);
}

}  // namespace hal
