#pragma once
// The status word published with every estimate. Bits 0-15 belong to the filter loop, bits 16-31 to the transports.
#include <cstdint>

#include "est/loop/status.hpp"

namespace hal::status {

// Filter loop: one definition, the firmware's (est/loop/status.hpp: kEncoderTimeout, kInputRejected, ... and each
// input kind's staleness bit), under hal's name too.
using namespace est::loop::status;

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
