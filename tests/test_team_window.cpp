#include <catch2/catch.hpp>

#include <algorithm>
#include <cstdint>
#include <vector>

#include "est/team/team_window.hpp"

namespace {

using est::team::TeamMessage;
using est::team::TeamReject;

TeamMessage msg(std::int32_t robot, std::uint32_t seq) {
  TeamMessage m;
  m.robot = robot;
  m.seq = seq;
  m.control.kind = est::team::ControlKind::holonomic;
  m.control.dt_s = 0.1f;
  m.control.v1 = static_cast<float>(seq) + 0.01f * static_cast<float>(robot);
  return m;
}

// What a closed step held: seq and, per robot, the control's v1 or -1 when absent.
struct Closed {
  std::uint32_t seq;
  std::vector<float> v1;
  bool operator==(const Closed& o) const { return seq == o.seq && v1 == o.v1; }
};

template <int R, int W>
struct Recorder {
  est::team::TeamWindow<R, W> w;
  std::vector<Closed> closed;
  TeamReject push(const TeamMessage& m) {
    return w.push(m, [this](std::uint32_t seq, const TeamMessage* const* msgs) {
      Closed c{seq, {}};
      for (int a = 0; a < w.robots(); ++a) c.v1.push_back(msgs[a] != nullptr ? msgs[a]->control.v1 : -1.0f);
      closed.push_back(c);
    });
  }
};

}  // namespace

TEST_CASE("team window: a step closes once every robot's message is in, in step order, robot 0 first") {
  Recorder<3, 4> r;
  REQUIRE(r.w.start(3, 1));
  CHECK(r.push(msg(2, 1)) == TeamReject::none);
  CHECK(r.push(msg(0, 2)) == TeamReject::none);
  CHECK(r.push(msg(0, 1)) == TeamReject::none);
  CHECK(r.closed.empty());
  CHECK(r.push(msg(1, 1)) == TeamReject::none);
  REQUIRE(r.closed.size() == 1);
  CHECK(r.closed[0] == Closed{1, {1.0f, 1.01f, 1.02f}});
  CHECK(r.w.next_step() == 2);
  CHECK(r.w.counters().steps_complete == 1);
}

TEST_CASE("team window: any arrival order within the window closes the same steps with the same messages") {
  std::vector<TeamMessage> all;
  for (std::uint32_t k = 1; k <= 40; ++k)
    for (int a = 0; a < 3; ++a) all.push_back(msg(a, k));
  Recorder<3, 8> ref;
  REQUIRE(ref.w.start(3, 1));
  for (const TeamMessage& m : all) REQUIRE(ref.push(m) == TeamReject::none);
  REQUIRE(ref.closed.size() == 40);
  std::uint64_t s = 88172645463325252ull;
  for (int trial = 0; trial < 20; ++trial) {
    // Shuffle inside blocks of 6 steps: each message at most 5 steps out of place, less than the window.
    std::vector<TeamMessage> shuffled = all;
    for (std::size_t b = 0; b < shuffled.size(); b += 18) {
      const std::size_t e = std::min(shuffled.size(), b + 18);
      for (std::size_t i = e - 1; i > b; --i) {
        s ^= s << 13, s ^= s >> 7, s ^= s << 17;
        std::swap(shuffled[i], shuffled[b + s % (i - b + 1)]);
      }
    }
    Recorder<3, 8> r;
    REQUIRE(r.w.start(3, 1));
    for (const TeamMessage& m : shuffled) REQUIRE(r.push(m) == TeamReject::none);
    CHECK(r.closed == ref.closed);
  }
}

TEST_CASE("team window: a silent robot's step closes W steps later without it; its message is then late") {
  Recorder<2, 4> r;
  REQUIRE(r.w.start(2, 1));
  r.push(msg(0, 1));
  for (std::uint32_t k = 2; k <= 4; ++k) r.push(msg(0, k)), r.push(msg(1, k));
  CHECK(r.closed.empty());  // step 1 waits for robot 1, and steps 2-4 wait behind it
  r.push(msg(0, 5));        // step 5 = 1 + W: step 1 closes without robot 1, then the complete 2-4
  REQUIRE(r.closed.size() == 4);
  CHECK(r.closed[0] == Closed{1, {1.0f, -1.0f}});
  CHECK(r.closed[3] == Closed{4, {4.0f, 4.01f}});
  CHECK(r.w.counters().missing[1] == 1);
  CHECK(r.w.counters().missing[0] == 0);
  CHECK(r.push(msg(1, 1)) == TeamReject::late);
  CHECK(r.w.counters().of(TeamReject::late) == 1);
  r.w.flush([&](std::uint32_t seq, const TeamMessage* const* m) {
    r.closed.push_back({seq, {m[0] != nullptr ? m[0]->control.v1 : -1.0f, m[1] != nullptr ? m[1]->control.v1 : -1.0f}});
  });
  CHECK(r.closed.back() == Closed{5, {5.0f, -1.0f}});
  CHECK(r.w.counters().steps_closed == 5);
}

TEST_CASE("team window: duplicates, unknown robots, malformed messages and wild sequence numbers are refused") {
  Recorder<2, 4> r;
  REQUIRE(r.w.start(2, 1, 100));
  CHECK(r.push(msg(0, 3)) == TeamReject::none);
  CHECK(r.push(msg(0, 3)) == TeamReject::duplicate);
  CHECK(r.push(msg(2, 3)) == TeamReject::unknown_robot);
  TeamMessage bad = msg(1, 3);
  bad.control.v2 = 0.0f / 0.0f;
  CHECK(r.push(bad) == TeamReject::malformed);
  bad = msg(1, 3);
  bad.count = 1;
  bad.measurements[0].target = est::team::TargetKind::robot;
  bad.measurements[0].id = 1;  // the sender measuring itself
  CHECK(r.push(bad) == TeamReject::unknown_robot);
  CHECK(r.push(msg(1, 3 + 101)) == TeamReject::malformed);  // more than max_jump ahead of the newest
  CHECK(r.closed.empty());
  CHECK(r.w.counters().of(TeamReject::duplicate) == 1);
  CHECK(r.w.counters().of(TeamReject::unknown_robot) == 2);
  CHECK(r.w.counters().of(TeamReject::malformed) == 2);
  CHECK(r.w.counters().accepted == 1);
  Recorder<2, 4> none;
  CHECK_FALSE(none.w.start(3));  // more robots than the window's capacity
  CHECK(none.push(msg(0, 1)) == TeamReject::unknown_robot);
}

TEST_CASE("team window: a long silence of the whole team is crossed step by step, each robot missing") {
  Recorder<2, 4> r;
  REQUIRE(r.w.start(2, 1));
  r.push(msg(0, 1)), r.push(msg(1, 1));
  r.push(msg(0, 50));
  // Steps 2..46 closed empty (50 - W), step 1 complete.
  REQUIRE(r.closed.size() == 46);
  CHECK(r.closed[1] == Closed{2, {-1.0f, -1.0f}});
  CHECK(r.w.counters().missing[0] == 45);
  CHECK(r.w.counters().missing[1] == 45);
}
