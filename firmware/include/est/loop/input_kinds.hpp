#pragma once
// The loop's input kinds in one table: each kind's payload (est/loop/inputs.hpp), its role in the loop, the status
// bit raised while it is stale, and its default staleness limit. The queue's tie order, the staleness checks, the
// status word and the per-kind counters (est/loop/loop_counters.hpp) are all driven by this table; a new kind is a
// row here, a payload in inputs.hpp and, for a motion kind, its share of est/loop/motion_input.hpp.
//
// Roles:
//  - increment: motion over (previous stamp, stamp] (encoder ticks, odometry increments); summed into the motion
//    since the last prediction, and split at a correction's time when the next increment spans it.
//  - held: a value that holds from its stamp until the next sample (steering, twist).
//  - measurement: applied as a correction at its own time (scans, landmark features).
#include <cstddef>
#include <cstdint>

#include "est/loop/inputs.hpp"
#include "est/loop/status.hpp"

namespace est::loop {

// Table order is the tie order of inputs with equal stamps: motion first, then corrections.
enum class InputKind : std::uint8_t { wheel_ticks = 0, steering, twist, odometry, scan, landmark };
inline constexpr std::size_t kInputKindCount = 6;

enum class InputRole : std::uint8_t { increment, held, measurement };

struct InputKindInfo {
  InputKind kind;
  const char* name;
  InputRole role;
  std::uint32_t stale_bit;       // est::loop::status bit while no sample is within the staleness limit
  TimeNs default_staleness_ns;   // LoopTiming's default limit
};

inline constexpr InputKindInfo kInputKinds[kInputKindCount] = {
    {InputKind::wheel_ticks, "wheel_ticks", InputRole::increment, status::kEncoderTimeout, 100000000},
    {InputKind::steering, "steering", InputRole::held, status::kSteeringTimeout, 100000000},
    {InputKind::twist, "twist", InputRole::held, status::kTwistTimeout, 100000000},
    {InputKind::odometry, "odometry", InputRole::increment, status::kOdometryTimeout, 100000000},
    {InputKind::scan, "scan", InputRole::measurement, status::kScanTimeout, 500000000},
    {InputKind::landmark, "landmark", InputRole::measurement, status::kLandmarkTimeout, 1000000000},
};

constexpr std::size_t index_of(InputKind k) { return static_cast<std::size_t>(k); }
constexpr const InputKindInfo& info(InputKind k) { return kInputKinds[index_of(k)]; }

// A set of kinds (what an estimator uses).
class InputKinds {
 public:
  constexpr InputKinds() = default;
  constexpr InputKinds(InputKind k) : bits_(bit(k)) {}  // NOLINT: a kind is the set of that kind
  constexpr InputKinds operator|(InputKinds o) const { return from_bits(bits_ | o.bits_); }
  constexpr InputKinds without(InputKind k) const { return from_bits(bits_ & ~bit(k)); }
  constexpr bool has(InputKind k) const { return (bits_ & bit(k)) != 0u; }
  constexpr bool empty() const { return bits_ == 0u; }
  constexpr bool operator==(InputKinds o) const { return bits_ == o.bits_; }

 private:
  static constexpr std::uint32_t bit(InputKind k) { return 1u << static_cast<std::uint32_t>(k); }
  static constexpr InputKinds from_bits(std::uint32_t b) {
    InputKinds s;
    s.bits_ = b;
    return s;
  }
  std::uint32_t bits_ = 0u;
};
constexpr InputKinds operator|(InputKind a, InputKind b) { return InputKinds(a) | InputKinds(b); }

// The kind of a payload type.
template <typename Payload>
struct KindOf;
template <> struct KindOf<WheelTicksInput> { static constexpr InputKind value = InputKind::wheel_ticks; };
template <> struct KindOf<SteeringInput> { static constexpr InputKind value = InputKind::steering; };
template <> struct KindOf<TwistInput> { static constexpr InputKind value = InputKind::twist; };
template <> struct KindOf<OdometryInput> { static constexpr InputKind value = InputKind::odometry; };
template <> struct KindOf<ScanInput> { static constexpr InputKind value = InputKind::scan; };
template <> struct KindOf<LandmarkInput> { static constexpr InputKind value = InputKind::landmark; };

// Staleness limits per kind, defaulting to the table's.
struct StalenessLimits {
  TimeNs ns[kInputKindCount] = {kInputKinds[0].default_staleness_ns, kInputKinds[1].default_staleness_ns,
                                kInputKinds[2].default_staleness_ns, kInputKinds[3].default_staleness_ns,
                                kInputKinds[4].default_staleness_ns, kInputKinds[5].default_staleness_ns};
  constexpr TimeNs& operator[](InputKind k) { return ns[index_of(k)]; }
  constexpr TimeNs operator[](InputKind k) const { return ns[index_of(k)]; }
};

}  // namespace est::loop
