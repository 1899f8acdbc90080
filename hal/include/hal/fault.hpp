#pragma once
// Why an input was rejected, and a counter per reason: rejects are values, counted, never silent.
#include <cstddef>
#include <cstdint>

namespace hal {

enum class Fault : std::uint8_t {
  none = 0,             // accepted
  not_finite,           // NaN or infinity where a number is required
  out_of_range,         // outside the configured physical limits (or an impossible shape)
  time_backwards,       // older than the last accepted sample of this kind
  duplicate,            // same timestamp as the last accepted sample of this kind
  stale,                // older than the staleness limit when it reached the HAL
  from_future,          // stamped ahead of the clock by more than the allowed skew
  bad_geometry,         // scan angles or range limits that cannot describe a scan
  too_few_valid_beams,  // fewer usable beams than configured
  kCount
};

inline constexpr std::size_t kFaultCount = static_cast<std::size_t>(Fault::kCount);

const char* to_string(Fault f);

// A saturating counter per reason of an enum whose last enumerator is kCount.
template <typename Reason, std::size_t N = static_cast<std::size_t>(Reason::kCount)>
struct ReasonCounters {
  std::uint32_t count[N] = {};

  void add(Reason r) {
    const auto i = static_cast<std::size_t>(r);
    if (i < N && count[i] != UINT32_MAX) ++count[i];
  }
  std::uint32_t operator[](Reason r) const {
    const auto i = static_cast<std::size_t>(r);
    return i < N ? count[i] : 0u;
  }
  // Every reason but the first (which is "none" by convention).
  std::uint32_t total() const {
    std::uint64_t sum = 0;
    for (std::size_t i = 1; i < N; ++i) sum += count[i];
    return sum > UINT32_MAX ? UINT32_MAX : static_cast<std::uint32_t>(sum);
  }
  void merge(const ReasonCounters& o) {
    for (std::size_t i = 0; i < N; ++i) {
      const std::uint64_t s = std::uint64_t{count[i]} + o.count[i];
      count[i] = s > UINT32_MAX ? UINT32_MAX : static_cast<std::uint32_t>(s);
    }
  }
};

using FaultCounters = ReasonCounters<Fault>;

}  // namespace hal
