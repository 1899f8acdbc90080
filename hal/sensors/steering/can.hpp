#pragma once
// The steering angle on the bus (STEERING, estimator.dbc): Motorola byte order, as steering angle sensors send it.
#include <cstddef>
#include <cstdint>

#include "hal/can/codec.hpp"
#include "hal/sensors/steering/steering.hpp"

namespace hal::can {

namespace dbc {
inline constexpr std::uint32_t kSteeringId = 0x101;
enum SteeringSignal : std::size_t { kSteeringAngle, kSteeringCounter, kSteeringChecksum };
inline constexpr SignalSpec kSteeringSignals[] = {
    {"SteeringAngle", 7, 16, BE, true, 0.0001f, 0.0f, -3.2768f, 3.2767f, "rad"},
    {"Counter", 51, 4, BE, false, 1.0f, 0.0f, 0.0f, 15.0f, ""},
    {"Checksum", 63, 8, BE, false, 1.0f, 0.0f, 0.0f, 255.0f, ""},
};
}  // namespace dbc

struct SteeringMsg {
  float angle_rad = 0.0f;
  std::uint8_t counter = 0;
};

CodecStatus encode(const SteeringMsg& m, CanFrame& f);
CodecStatus decode(const CanFrame& f, SteeringMsg& m);

inline SteeringSample to_sample(const SteeringMsg& m, TimeNs stamp_ns) { return {stamp_ns, m.angle_rad}; }
inline SteeringMsg to_message(const SteeringSample& s, std::uint8_t counter) { return {s.angle_rad, counter}; }

}  // namespace hal::can
