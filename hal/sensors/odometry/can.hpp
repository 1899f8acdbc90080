#pragma once
// The odometry pose on the bus (ODOMETRY, estimator.dbc) as wrapping fixed-point counters, so that a lost frame
// loses nothing but resolution (the next pose differs from the last one received) and the position never overflows:
// x and y in millimetres modulo 2^18 (262.144 m, plenty for one frame's motion), theta in 2^-16 turns. The receiver
// differences them modulo their periods (OdometrySample::wrap_m; hal/sensors/odometry/validator.hpp).
#include <cstddef>
#include <cstdint>

#include "hal/can/codec.hpp"
#include "hal/sensors/odometry/odometry.hpp"

namespace hal::can {

namespace dbc {
inline constexpr std::uint32_t kOdometryId = 0x104;
inline constexpr float kOdometryWrapM = 262.144f;                   // 2^18 mm
inline constexpr float kOdometryThetaStep = 9.5873799242852573e-05f; // 2 pi / 2^16 rad
enum OdometrySignal : std::size_t { kOdomX, kOdomY, kOdomTheta, kOdomCounter, kOdomChecksum };
inline constexpr SignalSpec kOdometrySignals[] = {
    {"X", 0, 18, LE, false, 1.0f, 0.0f, 0.0f, 262143.0f, "mm"},
    {"Y", 18, 18, LE, false, 1.0f, 0.0f, 0.0f, 262143.0f, "mm"},
    {"Theta", 36, 16, LE, false, 1.0f, 0.0f, 0.0f, 65535.0f, "turn/65536"},
    {"Counter", 52, 4, LE, false, 1.0f, 0.0f, 0.0f, 15.0f, ""},
    {"Checksum", 56, 8, LE, false, 1.0f, 0.0f, 0.0f, 255.0f, ""},
};
}  // namespace dbc

struct OdometryMsg {
  std::uint32_t x_mm = 0;  // modulo 2^18
  std::uint32_t y_mm = 0;
  std::uint16_t theta = 0; // 2^-16 turns, counter-clockwise
  std::uint8_t counter = 0;
};

CodecStatus encode(const OdometryMsg& m, CanFrame& f);
CodecStatus decode(const CanFrame& f, OdometryMsg& m);

// A pose to the wrapping counters (any finite pose: x, y and theta are reduced modulo their periods); false if not
// finite.
bool to_message(const OdometrySample& s, std::uint8_t counter, OdometryMsg& m);
OdometrySample to_sample(const OdometryMsg& m, TimeNs stamp_ns);

}  // namespace hal::can
