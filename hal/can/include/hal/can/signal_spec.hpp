#pragma once
// How estimator.dbc describes a message and its signals, as constant tables in flash. Each message's table sits
// with its sensor (hal/sensors/<sensor>/can.hpp) or with the estimate frames (hal/can/estimate_frames.hpp);
// hal/can/estimator_dbc.hpp gathers them, and tests/test_can_dbc.cpp requires them to match the DBC file.
#include <cstddef>
#include <cstdint>

namespace hal::can {

enum class ByteOrder : std::uint8_t { little_endian, big_endian };  // DBC @1 (Intel), @0 (Motorola)

struct SignalSpec {
  const char* name;
  std::uint16_t start_bit;  // DBC numbering: Intel = LSB position; Motorola = MSB position (bit 7 of byte 0 is 7)
  std::uint8_t length;
  ByteOrder order;
  bool is_signed;
  float factor;
  float offset;
  float minimum;
  float maximum;
  const char* unit;
};

struct MessageSpec {
  const char* name;
  std::uint32_t id;
  std::uint8_t dlc;
  const char* sender;
  const SignalSpec* signals;
  std::size_t signal_count;
};

namespace dbc {
inline constexpr auto LE = ByteOrder::little_endian;
inline constexpr auto BE = ByteOrder::big_endian;

template <std::size_t N>
constexpr std::size_t count_of(const SignalSpec (&)[N]) {
  return N;
}
}  // namespace dbc

}  // namespace hal::can
