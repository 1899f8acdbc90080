#pragma once
// The twist on the bus (TWIST, estimator.dbc): v1, v2 at 1 mm/s and w at 1 mrad/s, signed 16 bits each.
#include <cstddef>
#include <cstdint>

#include "hal/can/codec.hpp"
#include "hal/sensors/twist/twist.hpp"

namespace hal::can {

namespace dbc {
inline constexpr std::uint32_t kTwistId = 0x103;
enum TwistSignal : std::size_t { kTwistV1, kTwistV2, kTwistW, kTwistCounter, kTwistChecksum };
inline constexpr SignalSpec kTwistSignals[] = {
    {"V1", 0, 16, LE, true, 0.001f, 0.0f, -32.768f, 32.767f, "m/s"},
    {"V2", 16, 16, LE, true, 0.001f, 0.0f, -32.768f, 32.767f, "m/s"},
    {"W", 32, 16, LE, true, 0.001f, 0.0f, -32.768f, 32.767f, "rad/s"},
    {"Counter", 48, 4, LE, false, 1.0f, 0.0f, 0.0f, 15.0f, ""},
    {"Checksum", 56, 8, LE, false, 1.0f, 0.0f, 0.0f, 255.0f, ""},
};
}  // namespace dbc

struct TwistMsg {
  float v1_mps = 0.0f;
  float v2_mps = 0.0f;
  float w_rps = 0.0f;
  std::uint8_t counter = 0;
};

CodecStatus encode(const TwistMsg& m, CanFrame& f);
CodecStatus decode(const CanFrame& f, TwistMsg& m);

inline TwistSample to_sample(const TwistMsg& m, TimeNs stamp_ns) { return {stamp_ns, m.v1_mps, m.v2_mps, m.w_rps}; }
inline TwistMsg to_message(const TwistSample& s, std::uint8_t counter) {
  return {s.v1_mps, s.v2_mps, s.w_rps, counter};
}

}  // namespace hal::can
