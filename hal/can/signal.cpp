// Signal packing (hal/can/signal.hpp), following the DBC conventions that cantools and Vector tools use.
#include "hal/can/signal.hpp"

#include "hal/can/frame.hpp"

namespace hal::can {

namespace {

// Bit positions in DBC "sawtooth" numbering: bit b of byte n is n * 8 + b (b = 0 is the LSB of the byte).
// Intel signals run from the LSB upwards through the bytes; Motorola signals run from the MSB (start bit)
// downwards within a byte and continue at bit 7 of the next byte.
constexpr unsigned kBits = 8u * kMaxDlc;

inline bool get_bit(const std::uint8_t* d, unsigned pos) {
  return ((static_cast<unsigned>(d[pos / 8u]) >> (pos % 8u)) & 1u) != 0u;
}
inline void put_bit(std::uint8_t* d, unsigned pos, bool v) {
  const unsigned m = 1u << (pos % 8u);
  const unsigned byte = d[pos / 8u];
  d[pos / 8u] = static_cast<std::uint8_t>((v ? (byte | m) : (byte & ~m)) & 0xFFu);
}
inline unsigned motorola_next(unsigned pos) { return (pos % 8u == 0u) ? pos + 15u : pos - 1u; }

float round_half_away(float x) {
  // No libm: truncation of x +- 0.5 in 64-bit integers (|x| < 2^62 guaranteed by the caller's range check).
  return x >= 0.0f ? static_cast<float>(static_cast<std::int64_t>(x + 0.5f))
                   : -static_cast<float>(static_cast<std::int64_t>(-x + 0.5f));
}

}  // namespace

std::uint64_t extract_raw(const std::uint8_t* data, const SignalSpec& s) {
  std::uint64_t raw = 0;
  if (s.order == ByteOrder::little_endian) {
    for (unsigned i = 0; i < s.length; ++i) {
      const unsigned pos = s.start_bit + i;
      if (pos < kBits && get_bit(data, pos)) raw |= std::uint64_t{1} << i;
    }
  } else {
    unsigned pos = s.start_bit;
    for (unsigned i = 0; i < s.length && pos < kBits; ++i) {
      raw = (raw << 1) | (get_bit(data, pos) ? 1u : 0u);
      pos = motorola_next(pos);
    }
  }
  return raw;
}

void insert_raw(std::uint8_t* data, const SignalSpec& s, std::uint64_t raw) {
  if (s.order == ByteOrder::little_endian) {
    for (unsigned i = 0; i < s.length; ++i) {
      const unsigned pos = s.start_bit + i;
      if (pos < kBits) put_bit(data, pos, ((raw >> i) & 1u) != 0u);
    }
  } else {
    unsigned pos = s.start_bit;
    for (unsigned i = 0; i < s.length && pos < kBits; ++i) {
      put_bit(data, pos, ((raw >> (s.length - 1u - i)) & 1u) != 0u);
      pos = motorola_next(pos);
    }
  }
}

std::int64_t raw_to_integer(std::uint64_t raw, const SignalSpec& s) {
  if (!s.is_signed || s.length == 0 || s.length >= 64) return static_cast<std::int64_t>(raw);
  const std::uint64_t sign = std::uint64_t{1} << (s.length - 1u);
  if ((raw & sign) == 0u) return static_cast<std::int64_t>(raw);
  return static_cast<std::int64_t>(raw) - static_cast<std::int64_t>(sign << 1);
}

std::int64_t integer_min(const SignalSpec& s) {
  return s.is_signed ? -(std::int64_t{1} << (s.length - 1u)) : 0;
}

std::int64_t integer_max(const SignalSpec& s) {
  return s.is_signed ? (std::int64_t{1} << (s.length - 1u)) - 1 : (std::int64_t{1} << s.length) - 1;
}

float decode_physical(const std::uint8_t* data, const SignalSpec& s) {
  return static_cast<float>(raw_to_integer(extract_raw(data, s), s)) * s.factor + s.offset;
}

EncodeStatus encode_physical(std::uint8_t* data, const SignalSpec& s, float physical) {
  if (!__builtin_isfinite(physical)) return EncodeStatus::not_finite;
  const float half_step = 0.5f * s.factor;
  if (physical < s.minimum - half_step || physical > s.maximum + half_step) return EncodeStatus::out_of_range;
  const float scaled = round_half_away((physical - s.offset) / s.factor);
  const auto value = static_cast<std::int64_t>(scaled);
  if (value < integer_min(s) || value > integer_max(s)) return EncodeStatus::out_of_range;
  insert_raw(data, s, static_cast<std::uint64_t>(value));
  return EncodeStatus::ok;
}

EncodeStatus encode_integer(std::uint8_t* data, const SignalSpec& s, std::int64_t value) {
  if (value < integer_min(s) || value > integer_max(s)) return EncodeStatus::out_of_range;
  insert_raw(data, s, static_cast<std::uint64_t>(value));
  return EncodeStatus::ok;
}

}  // namespace hal::can
