#pragma once
// The status word published with every estimate. Bits 0-15 belong to the filter loop, bits 16-31 to the transports.
#include <cstdint>

#include "est/loop/status.hpp"

namespace hal::status {

// Filter loop: one definition, the firmware's (est/loop/status.hpp); these are the same constants under hal's name.
inline constexpr std::uint32_t kEncoderTimeout = est::loop::status::kEncoderTimeout;
inline constexpr std::uint32_t kSteeringTimeout = est::loop::status::kSteeringTimeout;
inline constexpr std::uint32_t kScanTimeout = est::loop::status::kScanTimeout;
inline constexpr std::uint32_t kInputRejected = est::loop::status::kInputRejected;  // by the loop or the HAL
inline constexpr std::uint32_t kFilterDegenerate = est::loop::status::kFilterDegenerate;
inline constexpr std::uint32_t kDeadlineOverrun = est::loop::status::kDeadlineOverrun;
inline constexpr std::uint32_t kNotInitialized = est::loop::status::kNotInitialized;
inline constexpr std::uint32_t kInputTooOld = est::loop::status::kInputTooOld;
inline constexpr std::uint32_t kQueueFull = est::loop::status::kQueueFull;
inline constexpr std::uint32_t kLandmarkTimeout = est::loop::status::kLandmarkTimeout;
inline constexpr std::uint32_t kTwistTimeout = est::loop::status::kTwistTimeout;
inline constexpr std::uint32_t kOdometryTimeout = est::loop::status::kOdometryTimeout;

// Transports.
inline constexpr std::uint32_t kCanLinkDown = 1u << 16;       // interface missing or down; reconnecting
inline constexpr std::uint32_t kCanBusOff = 1u << 17;         // controller reported bus-off (error frame)
inline constexpr std::uint32_t kCanErrorPassive = 1u << 18;   // controller error-passive (rx or tx)
inline constexpr std::uint32_t kCanErrorWarning = 1u << 19;   // controller error counters above the warning limit
inline constexpr std::uint32_t kCanRxOverflow = 1u << 20;     // frames lost in the kernel or controller queue
inline constexpr std::uint32_t kCanTxFailed = 1u << 21;       // a frame could not be queued for sending
inline constexpr std::uint32_t kCanProtocolError = 1u << 22;  // protocol violation, lost arbitration storm, no ack
inline constexpr std::uint32_t kLcmDecodeError = 1u << 24;    // an LCM message did not decode or had a bad shape

inline constexpr std::uint32_t kLoopMask = est::loop::status::kMask;
inline constexpr std::uint32_t kTransportMask = 0xffff0000u;

static_assert((kLoopMask & kTransportMask) == 0u && (kLoopMask | kTransportMask) == 0xffffffffu,
              "the loop and the transports share the status word without overlap");

}  // namespace hal::status
