#pragma once
// Wheel encoders on the bus (estimator.dbc): WHEEL_TICKS carries the counters of wheels 0 and 1 and the wheel count;
// a base with three or four wheels follows it with WHEEL_TICKS_EXT (wheels 2 and 3) under the same alive counter.
// Counters are 16 bits wide and wrap; the HAL unwraps them (hal/sensors/wheel_ticks/validator.hpp).
#include <cstddef>
#include <cstdint>

#include "hal/can/codec.hpp"
#include "hal/sensors/wheel_ticks/wheel_ticks.hpp"

namespace hal::can {

inline constexpr std::uint8_t kCanWheelCounterBits = 16;

namespace dbc {
inline constexpr std::uint32_t kWheelTicksId = 0x100;
inline constexpr std::uint32_t kWheelTicksExtId = 0x102;

enum WheelTicksSignal : std::size_t { kTicks0, kTicks1, kWheelCount, kWheelCounter, kWheelChecksum };
inline constexpr SignalSpec kWheelTicksSignals[] = {
    {"Ticks0", 0, 16, LE, false, 1.0f, 0.0f, 0.0f, 65535.0f, "tick"},
    {"Ticks1", 16, 16, LE, false, 1.0f, 0.0f, 0.0f, 65535.0f, "tick"},
    {"WheelCount", 32, 3, LE, false, 1.0f, 0.0f, 1.0f, 4.0f, ""},
    {"Counter", 48, 4, LE, false, 1.0f, 0.0f, 0.0f, 15.0f, ""},
    {"Checksum", 56, 8, LE, false, 1.0f, 0.0f, 0.0f, 255.0f, ""},
};
enum WheelTicksExtSignal : std::size_t { kTicks2, kTicks3, kWheelExtCounter, kWheelExtChecksum };
inline constexpr SignalSpec kWheelTicksExtSignals[] = {
    {"Ticks2", 0, 16, LE, false, 1.0f, 0.0f, 0.0f, 65535.0f, "tick"},
    {"Ticks3", 16, 16, LE, false, 1.0f, 0.0f, 0.0f, 65535.0f, "tick"},
    {"Counter", 48, 4, LE, false, 1.0f, 0.0f, 0.0f, 15.0f, ""},
    {"Checksum", 56, 8, LE, false, 1.0f, 0.0f, 0.0f, 255.0f, ""},
};
}  // namespace dbc

struct WheelTicksMsg {
  std::uint16_t ticks[2] = {};    // raw hardware counters of wheels 0 and 1 (wrap at 65536)
  std::uint8_t wheel_count = 2;   // 1..4; above 2 a WHEEL_TICKS_EXT frame follows
  std::uint8_t counter = 0;       // alive counter, 0..15
};
struct WheelTicksExtMsg {
  std::uint16_t ticks[2] = {};    // wheels 2 and 3
  std::uint8_t counter = 0;       // the WHEEL_TICKS frame's
};

CodecStatus encode(const WheelTicksMsg& m, CanFrame& f);
CodecStatus encode(const WheelTicksExtMsg& m, CanFrame& f);
CodecStatus decode(const CanFrame& f, WheelTicksMsg& m);
CodecStatus decode(const CanFrame& f, WheelTicksExtMsg& m);

// A sample as the frames a sender puts on the bus (one, or two for more than two wheels): the frames written.
std::size_t encode_wheel_ticks(const WheelTicks& s, std::uint8_t counter, CanFrame (&out)[2]);

// Pairs WHEEL_TICKS with its WHEEL_TICKS_EXT. A sample of three or four wheels waits for its second frame; a first
// frame that is not completed before the next WHEEL_TICKS is dropped (incomplete), and so is a second frame whose
// counter does not match the one waiting.
class WheelTicksFrames {
 public:
  struct Result {
    bool sample = false;      // `out` holds a complete sample
    bool incomplete = false;  // a first frame was dropped without its second, or a second frame had no first
  };
  Result on_first(const WheelTicksMsg& m, TimeNs stamp_ns, WheelTicks& out);
  Result on_second(const WheelTicksExtMsg& m, WheelTicks& out);

 private:
  WheelTicks pending_;
  std::uint8_t pending_counter_ = 0;
  bool waiting_ = false;
};

}  // namespace hal::can
