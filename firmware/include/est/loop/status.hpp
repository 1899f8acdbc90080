#pragma once
// The loop's health: a status word (bits 0-15; transports may use 16-31) and counters behind each bit.
#include <cstdint>

namespace est::loop {

namespace status {
inline constexpr std::uint32_t kEncoderTimeout = 1u << 0;    // no encoder sample within its staleness limit
inline constexpr std::uint32_t kSteeringTimeout = 1u << 1;
inline constexpr std::uint32_t kScanTimeout = 1u << 2;
inline constexpr std::uint32_t kInputRejected = 1u << 3;     // an input was rejected since the last output
inline constexpr std::uint32_t kFilterDegenerate = 1u << 4;  // weights collapsed / covariance repaired
inline constexpr std::uint32_t kDeadlineOverrun = 1u << 5;   // a step took longer than its budget
inline constexpr std::uint32_t kNotInitialized = 1u << 6;
inline constexpr std::uint32_t kInputTooOld = 1u << 7;       // older than the reorder window: dropped
inline constexpr std::uint32_t kQueueFull = 1u << 8;         // more pending inputs than the queue holds: dropped
inline constexpr std::uint32_t kLandmarkTimeout = 1u << 9;   // no landmark sighting within its staleness limit
inline constexpr std::uint32_t kMask = 0x0000ffffu;
}  // namespace status

struct LoopCounters {
  std::uint32_t inputs = 0;           // accepted into the queue
  std::uint32_t too_old = 0;          // dropped: older than what was already applied
  std::uint32_t queue_full = 0;       // dropped: no room
  std::uint32_t rejected = 0;         // refused by the estimator (bad control, bad scan)
  std::uint32_t predictions = 0;
  std::uint32_t corrections = 0;
  std::uint32_t degenerate = 0;
  std::uint32_t overruns = 0;         // steps over their deadline
  std::uint32_t encoder_timeouts = 0; // outputs published while the encoders were stale
  std::uint32_t steering_timeouts = 0;
  std::uint32_t scan_timeouts = 0;
  std::uint32_t landmark_timeouts = 0;
  std::uint32_t unused = 0;           // dropped: a kind of input the configured filter does not use (not a fault)
  std::int64_t worst_step_ns = 0;     // longest step measured through the clock
};

}  // namespace est::loop
