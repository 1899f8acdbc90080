// The encoder validator (hal/sensors/wheel_ticks/validator.hpp).
#include "hal/sensors/wheel_ticks/validator.hpp"

namespace hal {

Fault WheelTicksValidator::check(const WheelTicks& sample, TimeNs now_ns, WheelTickDelta& out) {
  if (sample.wheel_count != limits_.wheel_count || sample.wheel_count > kMaxWheels) return reject(Fault::out_of_range);
  const std::uint32_t mask = counter_mask(limits_.counter_bits);
  for (std::size_t w = 0; w < sample.wheel_count; ++w)
    if (sample.count[w] > mask) return reject(Fault::out_of_range);
  const Fault t = timing_.check(sample.stamp_ns, now_ns);
  if (t != Fault::none) return reject(t);

  out = WheelTickDelta{};
  out.stamp_ns = sample.stamp_ns;
  out.wheel_count = sample.wheel_count;
  if (!timing_.has_last() || sample.stamp_ns - timing_.last_ns() > limits_.max_gap_ns) {
    timing_.accept(sample.stamp_ns);
    last_ = sample;
    return Fault::none;
  }
  const TimeNs dt = sample.stamp_ns - timing_.last_ns();
  for (std::size_t w = 0; w < sample.wheel_count; ++w) {
    const std::int32_t d = counter_delta(sample.count[w], last_.count[w], limits_.counter_bits);
    const std::int64_t magnitude = d < 0 ? -std::int64_t{d} : std::int64_t{d};
    // |d| / dt > max rate, in integers: |d| < 2^31 and 1e9 < 2^30, so the product fits in 63 bits.
    if (magnitude * kNsPerS > std::int64_t{limits_.max_ticks_per_s} * dt) {
      timing_.accept(sample.stamp_ns);
      last_ = sample;
      return reject(Fault::out_of_range);
    }
    out.ticks[w] = d;
  }
  out.dt_ns = dt;
  timing_.accept(sample.stamp_ns);
  last_ = sample;
  return Fault::none;
}

}  // namespace hal
