#pragma once
// Time in the HAL: signed 64-bit nanoseconds of a monotonic clock (292 years of range, differences never wrap).
#include <cstdint>

namespace hal {

using TimeNs = std::int64_t;

inline constexpr TimeNs kNsPerMs = 1000000;
inline constexpr TimeNs kNsPerS = 1000000000;

// The monotonic clock port. The loop reads time only through it, so replay can drive time from a log.
class Clock {
 public:
  virtual TimeNs now_ns() = 0;

 protected:
  // Not virtual: a deleting destructor would reference operator delete on the board.
  ~Clock() = default;
};

}  // namespace hal
