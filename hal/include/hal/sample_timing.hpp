#pragma once
// The timing checks every sample kind shares: staleness, clock skew, monotonic and unique timestamps.
#include "hal/fault.hpp"
#include "hal/time.hpp"

namespace hal {

struct TimingLimits {
  TimeNs max_age_ns = 200 * kNsPerMs;   // older than this when it reaches the HAL: stale
  TimeNs max_future_ns = 5 * kNsPerMs;  // stamped ahead of the clock by more than this: from the future
};

class SampleTiming {
 public:
  explicit SampleTiming(const TimingLimits& limits = {}) : limits_(limits) {}

  // Checked before the sample's content, so a replayed or looped stream is caught whatever it carries.
  // Stamps come from the outside and may be anything: the differences saturate instead of overflowing.
  Fault check(TimeNs stamp_ns, TimeNs now_ns) const {
    if (exceeds(now_ns, stamp_ns, limits_.max_age_ns)) return Fault::stale;
    if (exceeds(stamp_ns, now_ns, limits_.max_future_ns)) return Fault::from_future;
    if (has_last_ && stamp_ns == last_ns_) return Fault::duplicate;
    if (has_last_ && stamp_ns < last_ns_) return Fault::time_backwards;
    return Fault::none;
  }
  void accept(TimeNs stamp_ns) {
    last_ns_ = stamp_ns;
    has_last_ = true;
  }
  bool has_last() const { return has_last_; }
  TimeNs last_ns() const { return last_ns_; }
  const TimingLimits& limits() const { return limits_; }

 private:
  // a - b > limit, for any a and b.
  static bool exceeds(TimeNs a, TimeNs b, TimeNs limit) {
    TimeNs d = 0;
    if (__builtin_sub_overflow(a, b, &d)) return a > b;
    return d > limit;
  }

  TimingLimits limits_;
  TimeNs last_ns_ = 0;
  bool has_last_ = false;
};

}  // namespace hal
