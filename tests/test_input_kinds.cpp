// The loop's table of input kinds (est/loop/input_kinds.hpp): one row per kind, in the order of the enum, each with
// its role, its own status bit and its default staleness; the set of kinds an estimator uses; the kind of each
// payload.
#include <catch2/catch.hpp>

#include <cstring>
#include <set>
#include <string>
#include <type_traits>

#include "est/loop/input_kinds.hpp"
#include "est/loop/loop_counters.hpp"
#include "est/loop/status.hpp"

using est::loop::InputKind;
using est::loop::InputKinds;
using est::loop::InputRole;
using est::loop::kInputKinds;

TEST_CASE("the table has one row per kind, in the enum's order, with unique names", "[input_kinds]") {
  REQUIRE(std::size(kInputKinds) == est::loop::kInputKindCount);
  std::set<std::string> names;
  for (std::size_t i = 0; i < est::loop::kInputKindCount; ++i) {
    INFO("row " << i);
    CHECK(est::loop::index_of(kInputKinds[i].kind) == i);
    CHECK(&est::loop::info(kInputKinds[i].kind) == &kInputKinds[i]);
    CHECK(names.insert(kInputKinds[i].name).second);
  }
  // The order is the tie order of equal stamps: the motion kinds first, then the corrections.
  const InputKind order[] = {InputKind::wheel_ticks, InputKind::steering, InputKind::twist,
                             InputKind::odometry,    InputKind::scan,     InputKind::landmark};
  for (std::size_t i = 0; i < std::size(order); ++i) CHECK(kInputKinds[i].kind == order[i]);
  bool seen_measurement = false;
  for (const auto& k : kInputKinds) {
    if (k.role == InputRole::measurement) seen_measurement = true;
    else CHECK_FALSE(seen_measurement);  // no motion kind sorts after a correction
  }
}

TEST_CASE("each kind has its role: increments, held values and measurements", "[input_kinds]") {
  CHECK(est::loop::info(InputKind::wheel_ticks).role == InputRole::increment);
  CHECK(est::loop::info(InputKind::odometry).role == InputRole::increment);
  CHECK(est::loop::info(InputKind::steering).role == InputRole::held);
  CHECK(est::loop::info(InputKind::twist).role == InputRole::held);
  CHECK(est::loop::info(InputKind::scan).role == InputRole::measurement);
  CHECK(est::loop::info(InputKind::landmark).role == InputRole::measurement);
}

TEST_CASE("each kind raises its own status bit, one of the loop's, never another meaning's", "[input_kinds]") {
  namespace st = est::loop::status;
  CHECK(est::loop::info(InputKind::wheel_ticks).stale_bit == st::kEncoderTimeout);
  CHECK(est::loop::info(InputKind::steering).stale_bit == st::kSteeringTimeout);
  CHECK(est::loop::info(InputKind::twist).stale_bit == st::kTwistTimeout);
  CHECK(est::loop::info(InputKind::odometry).stale_bit == st::kOdometryTimeout);
  CHECK(est::loop::info(InputKind::scan).stale_bit == st::kScanTimeout);
  CHECK(est::loop::info(InputKind::landmark).stale_bit == st::kLandmarkTimeout);
  std::uint32_t all = 0;
  for (const auto& k : kInputKinds) {
    INFO(k.name);
    CHECK((k.stale_bit & (k.stale_bit - 1u)) == 0u);  // one bit
    CHECK((k.stale_bit & all) == 0u);                 // its own
    CHECK((k.stale_bit & st::kMask) == k.stale_bit);  // the loop's half of the word
    all |= k.stale_bit;
  }
  const std::uint32_t others[] = {st::kInputRejected, st::kFilterDegenerate, st::kDeadlineOverrun,
                                  st::kNotInitialized, st::kInputTooOld,     st::kQueueFull};
  for (std::uint32_t b : others) CHECK((b & all) == 0u);
  // The wire formats' values (CAN ESTIMATOR_STATUS, LCM status_t) never move.
  CHECK(st::kTwistTimeout == (1u << 10));
  CHECK(st::kOdometryTimeout == (1u << 11));
}

TEST_CASE("staleness limits default to the table's and are set per kind", "[input_kinds]") {
  est::loop::StalenessLimits s;
  for (const auto& k : kInputKinds) CHECK(s[k.kind] == k.default_staleness_ns);
  CHECK(s[InputKind::scan] == 500000000);
  CHECK(s[InputKind::landmark] == 1000000000);
  s[InputKind::twist] = 42;
  CHECK(s[InputKind::twist] == 42);
  CHECK(s[InputKind::odometry] == est::loop::info(InputKind::odometry).default_staleness_ns);
  constexpr est::loop::StalenessLimits c{};
  static_assert(c[InputKind::steering] == 100000000, "usable in a static configuration");
}

TEST_CASE("a set of kinds: union, removal, membership", "[input_kinds]") {
  const InputKinds none;
  CHECK(none.empty());
  for (const auto& k : kInputKinds) CHECK_FALSE(none.has(k.kind));
  const InputKinds motion = InputKind::twist | InputKind::odometry;
  CHECK(motion.has(InputKind::twist));
  CHECK(motion.has(InputKind::odometry));
  CHECK_FALSE(motion.has(InputKind::wheel_ticks));
  const InputKinds all = motion | InputKind::scan;
  CHECK(all.has(InputKind::scan));
  CHECK(all.without(InputKind::scan) == motion);
  CHECK(all.without(InputKind::landmark) == all);  // removing what is not there changes nothing
  CHECK(InputKinds(InputKind::scan).without(InputKind::scan).empty());
  CHECK_FALSE(motion == all);
}

TEST_CASE("every payload knows its kind, and the counters hold one pair per kind", "[input_kinds]") {
  static_assert(est::loop::KindOf<est::loop::WheelTicksInput>::value == InputKind::wheel_ticks);
  static_assert(est::loop::KindOf<est::loop::SteeringInput>::value == InputKind::steering);
  static_assert(est::loop::KindOf<est::loop::TwistInput>::value == InputKind::twist);
  static_assert(est::loop::KindOf<est::loop::OdometryInput>::value == InputKind::odometry);
  static_assert(est::loop::KindOf<est::loop::ScanInput>::value == InputKind::scan);
  static_assert(est::loop::KindOf<est::loop::LandmarkInput>::value == InputKind::landmark);
  est::loop::LoopCounters c;
  c.of(InputKind::odometry).stale = 3;
  c.of(InputKind::twist).accepted = 5;
  CHECK(c.kinds[est::loop::index_of(InputKind::odometry)].stale == 3u);
  CHECK(c.kinds[est::loop::index_of(InputKind::twist)].accepted == 5u);
  const est::loop::LoopCounters& cc = c;
  CHECK(cc.of(InputKind::scan).stale == 0u);
  CHECK(std::size(c.kinds) == est::loop::kInputKindCount);
}
