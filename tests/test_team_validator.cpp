// The team validator: every refusal reason produced and counted exactly once per bad message (over the team and
// per sender), the receiver's own echo refused, out-of-order messages accepted and counted, duplicates caught after
// reordering and across the 64-seq window, senders tracked apart.
#include <catch2/catch.hpp>
#include <cstdint>
#include <limits>
#include <vector>

#include "hal/team/validator.hpp"

using est::team::ControlKind;
using est::team::TargetKind;
using est::team::TeamMessage;
using est::team::TeamReject;
using hal::team::TeamValidator;

namespace {

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
constexpr float kInf = std::numeric_limits<float>::infinity();

// A well-formed message: a velocity control, a landmark seen and robot 0 (or 1, by robot 0) seen.
TeamMessage good(std::int32_t robot, std::uint32_t seq) {
  TeamMessage m;
  m.robot = robot;
  m.seq = seq;
  m.stamp_ns = static_cast<est::team::TimeNs>(seq) * 100000000;
  m.control.kind = ControlKind::velocity;
  m.control.dt_s = 0.1f;
  m.control.v1 = 0.5f;
  m.control.w = 0.1f;
  m.count = 2;
  m.measurements[0] = {TargetKind::landmark, true, 4.0f, 0.5f, 12};
  m.measurements[1] = {TargetKind::robot, false, 2.0f, 0.0f, robot == 0 ? 1 : 0};
  return m;
}

struct Bad {
  const char* what;
  TeamMessage m;
  TeamReject why;
};

std::vector<Bad> bad_messages() {
  std::vector<Bad> b;
  auto add = [&b](const char* what, TeamReject why, auto&& edit) {
    TeamMessage m = good(1, 100);
    edit(m);
    b.push_back({what, m, why});
  };
  add("NaN velocity", TeamReject::malformed, [](TeamMessage& m) { m.control.v1 = kNaN; });
  add("infinite yaw rate", TeamReject::malformed, [](TeamMessage& m) { m.control.w = kInf; });
  add("NaN steering", TeamReject::malformed, [](TeamMessage& m) { m.control.steering_rad = kNaN; });
  add("zero dt with a control", TeamReject::malformed, [](TeamMessage& m) { m.control.dt_s = 0.0f; });
  add("dt over a second", TeamReject::malformed, [](TeamMessage& m) { m.control.dt_s = 1.5f; });
  add("unknown control kind", TeamReject::malformed,
      [](TeamMessage& m) { m.control.kind = static_cast<ControlKind>(est::team::kControlKindCount); });
  add("five wheels", TeamReject::malformed, [](TeamMessage& m) {
    m.control.kind = ControlKind::wheel_ticks;
    m.control.wheel_count = est::loop::kMaxWheels + 1;
  });
  add("negative count", TeamReject::malformed, [](TeamMessage& m) { m.count = -1; });
  add("count over the capacity", TeamReject::malformed,
      [](TeamMessage& m) { m.count = est::team::kMaxTeamMeasurements + 1; });
  add("NaN range", TeamReject::malformed, [](TeamMessage& m) { m.measurements[0].range_m = kNaN; });
  add("negative range", TeamReject::malformed, [](TeamMessage& m) { m.measurements[1].range_m = -0.5f; });
  add("bearing over pi", TeamReject::malformed, [](TeamMessage& m) { m.measurements[0].bearing_rad = 3.2f; });
  add("unknown target kind", TeamReject::malformed,
      [](TeamMessage& m) { m.measurements[1].target = static_cast<TargetKind>(2); });
  add("negative sender", TeamReject::unknown_robot, [](TeamMessage& m) { m.robot = -1; });
  add("sender outside the team", TeamReject::unknown_robot, [](TeamMessage& m) { m.robot = 4; });
  add("robot seen outside the team", TeamReject::unknown_robot, [](TeamMessage& m) { m.measurements[1].id = 4; });
  add("the sender sees itself", TeamReject::unknown_robot, [](TeamMessage& m) { m.measurements[1].id = 1; });
  add("own echo", TeamReject::unknown_robot, [](TeamMessage& m) { m.robot = 0; });
  return b;
}

}  // namespace

TEST_CASE("the well-formed message of each teammate is accepted in order", "[team]") {
  TeamValidator v(4, 0);
  for (std::int32_t r = 1; r < 4; ++r) CHECK(v.check(good(r, 1)) == TeamReject::none);
  CHECK(v.counts()[TeamReject::none] == 3u);
  CHECK(v.accepted() == 3u);
  CHECK(v.rejected() == 0u);
  CHECK(v.counts(2)[TeamReject::none] == 1u);
}

TEST_CASE("every refusal reason is produced and counted exactly once per bad message", "[team]") {
  TeamValidator v(4, 0);
  REQUIRE(v.check(good(1, 99)) == TeamReject::none);
  std::uint32_t refused = 0;
  for (const Bad& b : bad_messages()) {
    INFO(b.what);
    const hal::team::TeamRejectCounters before = v.counts();
    const hal::team::TeamRejectCounters before_sender = v.counts(b.m.robot);
    const TeamReject r = v.check(b.m);
    CHECK(r == b.why);
    CHECK_FALSE(TeamValidator::accepted(r));
    CHECK(v.counts()[b.why] == before[b.why] + 1u);
    CHECK(v.counts().total() == before.total() + 1u);
    CHECK(v.counts()[TeamReject::none] == before[TeamReject::none]);
    if (b.m.robot >= 0 && b.m.robot < 4) CHECK(v.counts(b.m.robot).total() == before_sender.total() + 1u);
    CHECK(v.rejected() == ++refused);
  }
  CHECK(v.counts()[TeamReject::late] == 0u);
  CHECK(v.counts()[TeamReject::capacity] == 0u);
  // None of them moved robot 1's sequence: its step 100 is still new.
  CHECK(v.check(good(1, 100)) == TeamReject::none);
}

TEST_CASE("the receiving robot's own message coming back from the network is refused as unknown_robot", "[team]") {
  TeamValidator v(3, 2);
  CHECK(v.check(good(2, 1)) == TeamReject::unknown_robot);
  CHECK(v.check(good(2, 2)) == TeamReject::unknown_robot);
  CHECK(v.counts(2)[TeamReject::unknown_robot] == 2u);
  CHECK(v.counts(1).total() == 0u);
  CHECK(v.check(good(1, 1)) == TeamReject::none);

  TeamValidator observer(3, hal::team::kNoRobot);  // a logger is no robot: every teammate's message passes
  for (std::int32_t r = 0; r < 3; ++r) CHECK(observer.check(good(r, 1)) == TeamReject::none);
}

TEST_CASE("out of order is accepted and counted; duplicates are caught after reordering", "[team]") {
  TeamValidator v(4, 0);
  std::vector<std::pair<std::uint32_t, TeamReject>> arrivals = {
      {1, TeamReject::none},         {3, TeamReject::none},      {2, TeamReject::out_of_order},
      {2, TeamReject::duplicate},    {3, TeamReject::duplicate}, {1, TeamReject::duplicate},
      {6, TeamReject::none},         {4, TeamReject::out_of_order}, {5, TeamReject::out_of_order},
      {4, TeamReject::duplicate},    {7, TeamReject::none}};
  for (const auto& [seq, why] : arrivals) {
    INFO("seq " << seq);
    CHECK(v.check(good(1, seq)) == why);
  }
  CHECK(v.counts()[TeamReject::none] == 4u);
  CHECK(v.counts()[TeamReject::out_of_order] == 3u);
  CHECK(v.counts()[TeamReject::duplicate] == 4u);
  CHECK(v.accepted() == 7u);
  CHECK(v.rejected() == 4u);
  CHECK(TeamValidator::accepted(TeamReject::out_of_order));
  CHECK(v.counts(1)[TeamReject::out_of_order] == 3u);
}

TEST_CASE("the 64-seq window: a duplicate 63 steps back is caught, 64 back passes on as out of order", "[team]") {
  TeamValidator v(4, 0);
  CHECK(v.check(good(1, 1000)) == TeamReject::none);
  CHECK(v.check(good(1, 937)) == TeamReject::out_of_order);  // 63 back, not seen
  CHECK(v.check(good(1, 937)) == TeamReject::duplicate);
  CHECK(v.check(good(1, 936)) == TeamReject::out_of_order);  // 64 back: the window refuses it as late
  CHECK(v.check(good(1, 936)) == TeamReject::out_of_order);
  CHECK(v.check(good(1, 1001)) == TeamReject::none);  // 937 is now 64 back, shifted out
  CHECK(v.check(good(1, 1000)) == TeamReject::duplicate);
  CHECK(v.check(good(1, 2000)) == TeamReject::none);  // a jump clears the mask
  CHECK(v.check(good(1, 1999)) == TeamReject::out_of_order);
  CHECK(v.check(good(1, 2000)) == TeamReject::duplicate);
  CHECK(v.check(good(1, 1937)) == TeamReject::out_of_order);
}

TEST_CASE("senders are tracked apart: the same seq from two robots is no duplicate", "[team]") {
  TeamValidator v(4, 0);
  CHECK(v.check(good(1, 5)) == TeamReject::none);
  CHECK(v.check(good(2, 5)) == TeamReject::none);
  CHECK(v.check(good(3, 4)) == TeamReject::none);  // robot 3's first: in order, whatever the others sent
  CHECK(v.check(good(2, 5)) == TeamReject::duplicate);
  CHECK(v.counts(1)[TeamReject::duplicate] == 0u);
  CHECK(v.counts(2)[TeamReject::duplicate] == 1u);
  CHECK(v.counts(2).total() == 1u);  // [none] is not a refusal
  CHECK(v.counts(9).total() == 0u);  // outside the team: zeros
  CHECK(v.counts(-1)[TeamReject::none] == 0u);
}

TEST_CASE("a team larger than a message can name refuses everything as unknown_robot", "[team]") {
  TeamValidator v(est::team::kMaxTeamRobots + 1, 0);
  CHECK(v.check(good(1, 1)) == TeamReject::unknown_robot);
  CHECK(v.counts()[TeamReject::unknown_robot] == 1u);
  CHECK(v.accepted() == 0u);
}
