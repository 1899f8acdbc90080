// The loop's input queue (est/loop/input_queue.hpp): timestamp order with ties in the table's order, landmark
// features of one time by their content, arrival order last; bounded capacity and scan slots (the readings are
// copied); the runtime-capacity interface over any storage.
#include <catch2/catch.hpp>

#include <algorithm>
#include <vector>

#include "est/loop/input_queue.hpp"
#include "est/random/xoshiro128.hpp"

namespace {

using est::loop::InputKind;
using est::loop::QueuedInput;
using est::loop::TimeNs;

est::loop::WheelTicksInput ticks(TimeNs t, std::int32_t n) {
  est::loop::WheelTicksInput in;
  in.t_ns = t;
  in.ticks[0] = n;
  in.wheel_count = 1;
  return in;
}

float g_range[4] = {1.0f, 2.0f, 3.0f, 4.0f};
est::loop::ScanInput scan(TimeNs t, std::int32_t count = 4) {
  return {t, est::ScanLayout{0.0f, 0.1f, count, 0.1f, 10.0f}, g_range};
}

// Pushes one input of `kind` at t.
bool push_kind(est::loop::InputQueue& q, InputKind kind, TimeNs t) {
  switch (kind) {
    case InputKind::wheel_ticks: return q.push(ticks(t, 1));
    case InputKind::steering: return q.push(est::loop::SteeringInput{t, 0.1f});
    case InputKind::twist: return q.push(est::loop::TwistInput{t, 0.5f, 0.0f, 0.0f});
    case InputKind::odometry: return q.push(est::loop::OdometryInput{t, {0.1f, 0.0f, 0.0f}});
    case InputKind::scan: return q.push(scan(t));
    case InputKind::landmark: return q.push(est::loop::LandmarkInput{t, 3.0f, 0.0f, 0.0f, 1});
  }
  return false;
}

std::vector<InputKind> drain(est::loop::InputQueue& q) {
  std::vector<InputKind> out;
  while (!q.empty()) {
    out.push_back(q.front().kind);
    q.pop();
  }
  return out;
}

}  // namespace

TEST_CASE("inputs with equal stamps come out in the table's order whatever order they were pushed in", "[input_queue]") {
  std::vector<InputKind> table;
  for (const auto& k : est::loop::kInputKinds) table.push_back(k.kind);
  std::vector<InputKind> arrival = table;
  est::Rng rng(5u);
  for (int round = 0; round < 20; ++round) {
    for (std::size_t i = arrival.size(); i > 1; --i)
      std::swap(arrival[i - 1], arrival[rng.below(static_cast<std::uint32_t>(i))]);
    est::loop::InputQueueStorage<16, 4, 2> q;
    for (InputKind k : arrival) REQUIRE(push_kind(q, k, 100));
    CHECK(drain(q) == table);
  }
}

TEST_CASE("time first, then kind, then arrival: one kind at one time keeps its arrival order", "[input_queue]") {
  est::loop::InputQueueStorage<16, 4, 2> q;
  q.push(ticks(20, 1));
  q.push(est::loop::TwistInput{10, 1.0f, 0.0f, 0.0f});
  q.push(ticks(10, 2));
  q.push(ticks(10, 3));
  q.push(est::loop::SteeringInput{5, 0.1f});
  std::vector<std::pair<TimeNs, std::int32_t>> out;
  while (!q.empty()) {
    const QueuedInput& f = q.front();
    out.push_back({f.t_ns, f.kind == InputKind::wheel_ticks ? f.p.ticks.ticks[0] : -1});
    q.pop();
  }
  const std::vector<std::pair<TimeNs, std::int32_t>> want = {{5, -1}, {10, 2}, {10, 3}, {10, -1}, {20, 1}};
  CHECK(out == want);
}

TEST_CASE("the features of one sighting come out by id, then range, whatever order they arrived in", "[input_queue]") {
  est::loop::InputQueueStorage<16, 4, 2> q;
  q.push(est::loop::LandmarkInput{7, 3.0f, 0.0f, 0.0f, 2});
  q.push(est::loop::LandmarkInput{7, 5.0f, 0.0f, 0.0f, -1});
  q.push(est::loop::LandmarkInput{7, 1.0f, 0.0f, 0.0f, 2});
  q.push(est::loop::LandmarkInput{7, 4.0f, 0.0f, 0.0f, -1});
  std::vector<std::pair<std::int32_t, float>> out;
  while (!q.empty()) {
    out.push_back({q.front().p.landmark.id, q.front().p.landmark.range_m});
    q.pop();
  }
  const std::vector<std::pair<std::int32_t, float>> want = {{-1, 4.0f}, {-1, 5.0f}, {2, 1.0f}, {2, 3.0f}};
  CHECK(out == want);
}

TEST_CASE("a full queue refuses instead of overwriting; a pop makes room", "[input_queue]") {
  est::loop::InputQueueStorage<3, 4, 1> q;
  est::loop::InputQueue& base = q;  // the loop sees only the runtime-capacity interface
  CHECK(base.capacity() == 3u);
  CHECK(base.max_beams() == 4);
  for (int i = 0; i < 3; ++i) CHECK(base.push(ticks(i, i)));
  CHECK_FALSE(base.push(ticks(9, 9)));
  CHECK_FALSE(base.push(est::loop::OdometryInput{9, {}}));
  CHECK(base.size() == 3u);
  CHECK(base.front_time() == 0);
  base.pop();
  CHECK(base.push(ticks(9, 9)));
  CHECK(base.size() == 3u);
}

TEST_CASE("scans are copied into a slot, bounded by KMax and the slots, and the slot is freed by pop", "[input_queue]") {
  est::loop::InputQueueStorage<8, 4, 1> q;
  float r[5] = {1.5f, 2.5f, 3.5f, 4.5f, 5.5f};
  CHECK_FALSE(q.push(est::loop::ScanInput{0, est::ScanLayout{0.0f, 0.1f, 5, 0.1f, 10.0f}, r}));  // more than KMax
  CHECK_FALSE(q.push(est::loop::ScanInput{0, est::ScanLayout{0.0f, 0.1f, 0, 0.1f, 10.0f}, r}));  // none
  CHECK_FALSE(q.push(est::loop::ScanInput{0, est::ScanLayout{0.0f, 0.1f, 2, 0.1f, 10.0f}, nullptr}));
  REQUIRE(q.push(est::loop::ScanInput{10, est::ScanLayout{-1.0f, 0.5f, 4, 0.2f, 8.0f}, r}));
  r[0] = -7.0f;  // the caller's buffer may change: the queue holds its own copy
  CHECK_FALSE(q.push(scan(20)));  // the one slot is taken
  CHECK(q.size() == 1u);
  const est::loop::ScanInput s = q.scan(q.front());
  CHECK(s.t_ns == 10);
  CHECK(s.layout.count == 4);
  CHECK(s.layout.angle_min == -1.0f);
  CHECK(s.layout.range_max == 8.0f);
  CHECK(s.ranges[0] == 1.5f);
  CHECK(s.ranges[3] == 4.5f);
  q.pop();
  CHECK(q.push(scan(20)));  // free again
}

TEST_CASE("the next queued input of a kind is found after the front and can be changed in place", "[input_queue]") {
  est::loop::InputQueueStorage<8, 4, 1> q;
  q.push(scan(5));
  q.push(ticks(3, 30));
  q.push(est::loop::OdometryInput{8, {0.2f, 0.0f, 0.0f}});
  q.push(ticks(9, 90));
  REQUIRE(q.front().kind == InputKind::wheel_ticks);  // the one at 3 ms
  QueuedInput* next = q.next_of_kind(InputKind::wheel_ticks);
  REQUIRE(next != nullptr);
  CHECK(next->t_ns == 9);  // not the front itself
  next->p.ticks.ticks[0] -= 40;
  CHECK(q.next_of_kind(InputKind::landmark) == nullptr);
  REQUIRE(q.next_of_kind(InputKind::odometry) != nullptr);
  CHECK(q.next_of_kind(InputKind::odometry)->p.odometry.increment.x == 0.2f);
  std::vector<InputKind> kinds = drain(q);
  CHECK(kinds == std::vector<InputKind>{InputKind::wheel_ticks, InputKind::scan, InputKind::odometry,
                                        InputKind::wheel_ticks});
}

TEST_CASE("twist, odometry and steering payloads come back as pushed", "[input_queue]") {
  est::loop::InputQueueStorage<8, 4, 1> q;
  q.push(est::loop::TwistInput{1, 0.5f, -0.25f, 0.125f});
  q.push(est::loop::OdometryInput{2, {0.1f, 0.2f, 0.3f}});
  q.push(est::loop::SteeringInput{3, -0.4f});
  REQUIRE(q.front().kind == InputKind::twist);
  CHECK(q.front().p.twist.v2_mps == -0.25f);
  CHECK(q.front().p.twist.w_rps == 0.125f);
  q.pop();
  REQUIRE(q.front().kind == InputKind::odometry);
  CHECK(q.front().p.odometry.increment.theta == 0.3f);
  q.pop();
  REQUIRE(q.front().kind == InputKind::steering);
  CHECK(q.front().p.steering.angle_rad == -0.4f);
  q.pop();
  CHECK(q.empty());
  q.pop();  // popping an empty queue does nothing
  CHECK(q.size() == 0u);
}
