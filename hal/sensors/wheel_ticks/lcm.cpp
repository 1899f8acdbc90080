// Wheel encoders on LCM (hal/sensors/wheel_ticks/lcm.hpp).
#include "hal/sensors/wheel_ticks/lcm.hpp"

namespace hal::lcm {

LcmReject to_hal(const est_lcm::encoder_ticks_t& m, unsigned expected_counter_bits, WheelTicks& out) {
  if (m.num_wheels < 1 || static_cast<std::size_t>(m.num_wheels) > kMaxWheels ||
      m.count.size() != static_cast<std::size_t>(m.num_wheels))
    return LcmReject::bad_count;
  if (m.counter_bits < 1 || m.counter_bits > 32 || static_cast<unsigned>(m.counter_bits) != expected_counter_bits)
    return LcmReject::bad_shape;
  out = WheelTicks{};
  out.stamp_ns = m.stamp_ns;
  out.wheel_count = static_cast<std::uint8_t>(m.num_wheels);
  for (std::size_t i = 0; i < out.wheel_count; ++i) out.count[i] = static_cast<std::uint32_t>(m.count[i]);
  return LcmReject::none;
}

est_lcm::encoder_ticks_t to_lcm(const WheelTicks& s, unsigned counter_bits) {
  est_lcm::encoder_ticks_t m{};
  m.stamp_ns = s.stamp_ns;
  m.counter_bits = static_cast<std::int8_t>(counter_bits);
  for (std::size_t i = 0; i < s.wheel_count && i < kMaxWheels; ++i)
    m.count.push_back(static_cast<std::int32_t>(s.count[i]));
  m.num_wheels = static_cast<std::int16_t>(m.count.size());
  return m;
}

}  // namespace hal::lcm
