#pragma once
// Packing one DBC signal into the 8 data bytes and back: raw bits, two's complement, factor and offset.
#include <cstdint>

#include "hal/can/signal_spec.hpp"

namespace hal::can {

// Raw bits of the signal, zero-extended.
std::uint64_t extract_raw(const std::uint8_t* data, const SignalSpec& s);
// Writes the low `length` bits of raw; the other bits of data are kept.
void insert_raw(std::uint8_t* data, const SignalSpec& s, std::uint64_t raw);

// Raw value as the signed or unsigned integer the DBC declares.
std::int64_t raw_to_integer(std::uint64_t raw, const SignalSpec& s);
std::int64_t integer_min(const SignalSpec& s);
std::int64_t integer_max(const SignalSpec& s);

// physical = raw * factor + offset (float, as the board computes it).
float decode_physical(const std::uint8_t* data, const SignalSpec& s);

enum class EncodeStatus : std::uint8_t { ok, not_finite, out_of_range };

// raw = round((physical - offset) / factor), rejected when not finite or outside the DBC's [minimum, maximum]
// (widened by half a step so that a decoded maximum re-encodes) or outside the raw integer range.
EncodeStatus encode_physical(std::uint8_t* data, const SignalSpec& s, float physical);
// Integer signals (counters, ids, words) go in exactly.
EncodeStatus encode_integer(std::uint8_t* data, const SignalSpec& s, std::int64_t value);

}  // namespace hal::can
