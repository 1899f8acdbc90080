#pragma once
// The loop's status word: bits 0-15 (transports may use 16-31). The per-kind staleness bits are named here and
// assigned to their input kinds by the table in est/loop/input_kinds.hpp; the counters behind each bit are in
// est/loop/loop_counters.hpp. Bit values are part of the wire formats (CAN ESTIMATOR_STATUS, LCM status_t): never
// renumber one.
#include <cstdint>

namespace est::loop::status {

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
inline constexpr std::uint32_t kTwistTimeout = 1u << 10;     // no twist within its staleness limit
inline constexpr std::uint32_t kOdometryTimeout = 1u << 11;  // no odometry increment within its staleness limit
inline constexpr std::uint32_t kTeamRobotMissing = 1u << 12;  // a teammate's step closed without its message
inline constexpr std::uint32_t kMask = 0x0000ffffu;

}  // namespace est::loop::status
