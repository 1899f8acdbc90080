#pragma once
// Decoding LCM messages from the network with the checks a receiver needs (host only): every est_lcm type that has
// arrays declares its count first, so the count is bounded before lcm-gen's decoder allocates for it; a message
// that does not decode exactly (fingerprint, truncation, trailing bytes) is malformed. Each type with arrays states
// the width of its leading count where its conversion lives (LeadingCount below).
#include <cstddef>
#include <cstdint>
#include <exception>

#include "hal/fault.hpp"

namespace hal::lcm {

enum class LcmReject : std::uint8_t {
  none = 0,
  malformed,   // lcm-gen's decoder failed (wrong fingerprint, truncated, trailing garbage)
  bad_count,   // an array count negative or above what the receiver holds
  bad_shape,   // fields inconsistent with the receiver's configuration (e.g. counter width)
  bad_value,   // content rejected by the HAL checks (counted by hal::Fault too)
  kCount
};
const char* to_string(LcmReject r);
using LcmRejectCounters = ReasonCounters<LcmReject>;

// Bytes of the array count a type declares first (0: no arrays).
template <typename Message>
struct LeadingCount {
  static constexpr int bytes = 0;
};

namespace detail {
// Big-endian signed integer of `bytes` bytes after the 8-byte type fingerprint.
inline bool read_leading_count(const unsigned char* p, std::size_t size, int bytes, std::int64_t& count) {
  if (size < static_cast<std::size_t>(8 + bytes)) return false;
  std::uint32_t v = 0;
  for (int i = 0; i < bytes; ++i) v = (v << 8) | p[8 + i];
  count = bytes == 2 ? static_cast<std::int64_t>(static_cast<std::int16_t>(v))
                     : static_cast<std::int64_t>(static_cast<std::int32_t>(v));
  return true;
}
}  // namespace detail

// Decodes msg from one LCM payload. max_count bounds the leading array count (ignored for types without arrays).
template <typename Message>
LcmReject decode_guarded(const void* data, std::size_t size, Message& msg, std::int64_t max_count) {
  if (data == nullptr || size > 0x7fffffffu) return LcmReject::malformed;
  constexpr int count_bytes = LeadingCount<Message>::bytes;
  if (count_bytes > 0) {
    std::int64_t n = 0;
    if (!detail::read_leading_count(static_cast<const unsigned char*>(data), size, count_bytes, n))
      return LcmReject::malformed;
    if (n < 0 || n > max_count) return LcmReject::bad_count;
  }
  // Later counts (status_t's) are not bounded above; a negative one makes lcm-gen's resize() throw.
  try {
    const int used = msg.decode(data, 0, static_cast<int>(size));
    if (used < 0 || static_cast<std::size_t>(used) != size) return LcmReject::malformed;
  } catch (const std::exception&) {
    return LcmReject::malformed;
  }
  return LcmReject::none;
}

}  // namespace hal::lcm
