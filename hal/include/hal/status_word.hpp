#pragma once
// The status word published with every estimate. Bits 0-15 belong to the filter loop, bits 16-31 to the transports.
#include <cstdint>

namespace hal::status {

// Filter loop.
inline constexpr std::uint32_t kEncoderTimeout = 1u << 0;
inline constexpr std::uint32_t kSteeringTimeout = 1u << 1;
inline constexpr std::uint32_t kScanTimeout = 1u << 2;
inline constexpr std::uint32_t kInputRejected = 1u << 3;     // at least one input rejected since the last estimate
inline constexpr std::uint32_t kFilterDegenerate = 1u << 4;  // e.g. particle weights collapsed, covariance not SPD
inline constexpr std::uint32_t kDeadlineOverrun = 1u << 5;
inline constexpr std::uint32_t kNotInitialized = 1u << 6;
inline constexpr std::uint32_t kInputsOutOfOrder = 1u << 7;  // a measurement older than the reorder window

// Transports.
inline constexpr std::uint32_t kCanLinkDown = 1u << 16;       // interface missing or down; reconnecting
inline constexpr std::uint32_t kCanBusOff = 1u << 17;         // controller reported bus-off (error frame)
inline constexpr std::uint32_t kCanErrorPassive = 1u << 18;   // controller error-passive (rx or tx)
inline constexpr std::uint32_t kCanErrorWarning = 1u << 19;   // controller error counters above the warning limit
inline constexpr std::uint32_t kCanRxOverflow = 1u << 20;     // frames lost in the kernel or controller queue
inline constexpr std::uint32_t kCanTxFailed = 1u << 21;       // a frame could not be queued for sending
inline constexpr std::uint32_t kCanProtocolError = 1u << 22;  // protocol violation, lost arbitration storm, no ack
inline constexpr std::uint32_t kLcmDecodeError = 1u << 24;    // an LCM message did not decode or had a bad shape

inline constexpr std::uint32_t kLoopMask = 0x0000ffffu;
inline constexpr std::uint32_t kTransportMask = 0xffff0000u;

}  // namespace hal::status
