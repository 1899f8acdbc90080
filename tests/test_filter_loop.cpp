#include <catch2/catch.hpp>
#include <algorithm>
#include <cstdint>
#include <vector>

#include "est/loop/filter_loop.hpp"
#include "est/random/xoshiro128.hpp"

namespace {

using est::loop::TimeNs;
constexpr TimeNs kMs = 1000000;

// Records every call, and integrates ticks into x so outputs depend on the order of calls.
struct RecordingEstimator {
  static constexpr bool kUsesSteering = true;
  static constexpr bool kUsesScans = true;
  static constexpr bool kUsesLandmarks = true;
  struct Call {
    char kind;
    float dt_s;
    std::int32_t left, right;
    float steering;
    float first_range;
    bool operator==(const Call& o) const {
      return kind == o.kind && dt_s == o.dt_s && left == o.left && right == o.right && steering == o.steering &&
             first_range == o.first_range;
    }
  };
  std::vector<Call> calls;
  float x = 0.0f;
  est::loop::StepOutcome predict(const est::loop::MotionInput& m) {
    calls.push_back({'p', m.dt_s, m.left_ticks, m.right_ticks, m.steering_rad, 0.0f});
    x += 0.001f * static_cast<float>(m.left_ticks + m.right_ticks) + 0.5f * m.steering_rad * m.dt_s;
    return est::loop::StepOutcome::applied;
  }
  est::loop::StepOutcome correct(const est::loop::ScanInput& s) {
    calls.push_back({'c', 0.0f, 0, 0, 0.0f, s.ranges[0]});
    if (!(s.ranges[0] > 0.0f)) return est::loop::StepOutcome::rejected;
    x = 0.5f * (x + s.ranges[0]);
    return est::loop::StepOutcome::applied;
  }
  est::loop::StepOutcome correct(const est::loop::LandmarkInput& z) {
    calls.push_back({'l', 0.0f, z.id, 0, 0.0f, z.range_m});
    if (!(z.range_m > 0.0f)) return est::loop::StepOutcome::rejected;
    x = 0.9f * x + 0.1f * z.range_m;
    return est::loop::StepOutcome::applied;
  }
  est::PoseEstimate estimate() const {
    est::PoseEstimate e;
    e.mean = {x, 0.0f, 0.0f};
    return e;
  }
};

struct SteadyClock {  // a step takes 1 us
  TimeNs t = 0;
  TimeNs operator()() { return t += 1000; }
};

struct Outputs {
  std::vector<est::loop::LoopOutput> all;
  void operator()(const est::loop::LoopOutput& o) { all.push_back(o); }
};

using Loop = est::loop::FilterLoop<RecordingEstimator, 64, 8, 2>;

struct Stream {
  std::vector<est::loop::WheelTicksInput> ticks;
  std::vector<est::loop::SteeringInput> steer;
  std::vector<std::pair<TimeNs, float>> scans;
};

Stream make_stream() {
  Stream s;
  for (int i = 1; i <= 100; ++i) s.ticks.push_back({i * 10 * kMs, i % 7, 2 * (i % 5)});   // 100 Hz encoders
  for (int i = 1; i <= 50; ++i) s.steer.push_back({i * 20 * kMs + 3 * kMs, 0.01f * static_cast<float>(i)});
  for (int i = 1; i <= 10; ++i) s.scans.push_back({i * 100 * kMs + 5 * kMs, 2.0f + 0.1f * static_cast<float>(i)});
  return s;
}

// Feeds the stream in the given arrival order (indices into one list of all inputs).
template <typename Order>
std::pair<std::vector<RecordingEstimator::Call>, std::vector<float>> feed(const Stream& s, Order order,
                                                                         std::uint32_t* dropped = nullptr) {
  struct Item {
    TimeNs t;
    int kind;
    std::size_t i;
  };
  std::vector<Item> items;
  for (std::size_t i = 0; i < s.ticks.size(); ++i) items.push_back({s.ticks[i].t_ns, 0, i});
  for (std::size_t i = 0; i < s.steer.size(); ++i) items.push_back({s.steer[i].t_ns, 1, i});
  for (std::size_t i = 0; i < s.scans.size(); ++i) items.push_back({s.scans[i].first, 2, i});
  std::sort(items.begin(), items.end(), [](const Item& a, const Item& b) { return a.t < b.t; });
  order(items);
  RecordingEstimator est;
  est::loop::LoopTiming timing;
  Loop loop(est, timing);
  SteadyClock clock;
  Outputs out;
  float ranges[8] = {};
  for (const Item& it : items) {
    if (it.kind == 0) loop.push(s.ticks[it.i]);
    if (it.kind == 1) loop.push(s.steer[it.i]);
    if (it.kind == 2) {
      ranges[0] = s.scans[it.i].second;
      est::ScanLayout layout{0.0f, 0.1f, 8, 0.1f, 10.0f};
      loop.push(est::loop::ScanInput{it.t, layout, ranges});
    }
    loop.run(clock, out);
  }
  loop.flush(clock, out);
  if (dropped) *dropped = loop.counters().too_old;
  std::vector<float> xs;
  for (const auto& o : out.all) xs.push_back(o.estimate.mean.x);
  return {est.calls, xs};
}

}  // namespace

TEST_CASE("inputs shuffled within the reorder window give bit-identical calls and outputs", "[loop]") {
  const Stream s = make_stream();
  const auto in_order = feed(s, [](auto&) {});
  // Swap neighbours up to 15 ms apart (the window is 20 ms): arrival order changes, timestamps do not.
  const auto shuffled = feed(s, [](auto& items) {
    est::Rng rng(3u);
    for (std::size_t i = 0; i + 1 < items.size(); ++i)
      if (items[i + 1].t - items[i].t <= 15 * kMs && rng.below(2u) == 1u) std::swap(items[i], items[i + 1]);
  });
  REQUIRE(in_order.first.size() > 100u);
  CHECK(in_order.first == shuffled.first);
  CHECK(in_order.second == shuffled.second);
}

TEST_CASE("prediction runs at the fixed period and consumes every tick exactly once", "[loop]") {
  const Stream s = make_stream();
  const auto r = feed(s, [](auto&) {});
  std::int64_t left = 0, right = 0, in_left = 0, in_right = 0;
  int fixed = 0;
  for (const auto& c : r.first) {
    if (c.kind != 'p') continue;
    left += c.left;
    right += c.right;
    if (c.dt_s == Approx(0.01f)) ++fixed;
  }
  for (const auto& t : s.ticks) {
    in_left += t.left_ticks;
    in_right += t.right_ticks;
  }
  // The last scan (1.005 s) comes after the last encoder sample (1.000 s), so its prediction consumes every tick.
  CHECK(left == in_left);
  CHECK(right == in_right);
  CHECK(fixed >= 90);  // 1 s at 100 Hz; the predictions split at the 10 scans are shorter
}

TEST_CASE("a scan is applied after a prediction up to its own time", "[loop]") {
  const Stream s = make_stream();
  const auto r = feed(s, [](auto&) {});
  int scans = 0;
  for (std::size_t i = 0; i < r.first.size(); ++i) {
    if (r.first[i].kind != 'c') continue;
    ++scans;
    REQUIRE(i > 0);
    CHECK(r.first[i - 1].kind == 'p');
    CHECK(r.first[i - 1].dt_s == Approx(0.005f).epsilon(1e-3));  // scans at +5 ms past a 10 ms tick
  }
  CHECK(scans == 10);
}

TEST_CASE("an input older than what was applied is dropped and counted", "[loop]") {
  const Stream s = make_stream();
  std::uint32_t dropped = 0;
  feed(s, [](auto& items) { std::rotate(items.begin() + 10, items.begin() + 11, items.begin() + 60); }, &dropped);
  CHECK(dropped == 1u);  // item 10 arrives ~ 250 ms late, far beyond the 20 ms window
}

TEST_CASE("stale sensors, rejected inputs and overruns show in the status word", "[loop]") {
  RecordingEstimator est;
  est::loop::LoopTiming timing;
  Loop loop(est, timing);
  Outputs out;
  struct SlowClock {  // every step takes 10 ms: over the 5 ms budget
    TimeNs t = 0;
    TimeNs operator()() { return t += 10 * kMs; }
  } slow;
  loop.push(est::loop::WheelTicksInput{0, 1, 1});
  float bad[1] = {-1.0f};
  loop.push(est::loop::ScanInput{300 * kMs, est::ScanLayout{0.0f, 0.1f, 1, 0.1f, 10.0f}, bad});
  loop.flush(slow, out);
  REQUIRE(!out.all.empty());
  const auto last = out.all.back();
  CHECK((last.status & est::loop::status::kEncoderTimeout) != 0u);   // no encoder sample for 300 ms
  CHECK((last.status & est::loop::status::kSteeringTimeout) != 0u);  // never any steering
  CHECK((last.status & est::loop::status::kInputRejected) != 0u);    // the scan with a negative range
  CHECK((last.status & est::loop::status::kDeadlineOverrun) != 0u);
  CHECK(loop.counters().rejected == 1u);
  CHECK(loop.counters().overruns > 0u);
  CHECK(loop.counters().worst_step_ns == 10 * kMs);
}

TEST_CASE("the clock never changes the estimates, only the timing figures", "[loop]") {
  auto run = [](TimeNs step) {
    RecordingEstimator est;
    Loop loop(est, est::loop::LoopTiming{});
    Outputs out;
    struct C {
      TimeNs t, step;
      TimeNs operator()() { return t += step; }
    } clock{0, step};
    for (int i = 1; i <= 50; ++i) {
      loop.push(est::loop::WheelTicksInput{i * 10 * kMs, 3, 4});
      loop.run(clock, out);
    }
    loop.flush(clock, out);
    std::vector<float> xs;
    for (const auto& o : out.all) xs.push_back(o.estimate.mean.x);
    return xs;
  };
  CHECK(run(1000) == run(50 * kMs));
}

TEST_CASE("a gap in the inputs is bridged by one prediction, not thousands", "[loop]") {
  RecordingEstimator est;
  Loop loop(est, est::loop::LoopTiming{});
  Outputs out;
  SteadyClock clock;
  loop.push(est::loop::WheelTicksInput{0, 0, 0});
  loop.push(est::loop::WheelTicksInput{60LL * 1000 * kMs, 5, 5});  // one minute later
  loop.flush(clock, out);
  CHECK(est.calls.size() <= 101u);
  CHECK(est.calls.back().dt_s > 58.0f);
}

TEST_CASE("a full queue drops and counts instead of overwriting", "[loop]") {
  RecordingEstimator est;
  est::loop::FilterLoop<RecordingEstimator, 4, 8, 1> loop(est, est::loop::LoopTiming{});
  for (int i = 0; i < 6; ++i) loop.push(est::loop::WheelTicksInput{i * kMs, 1, 1});  // all within the window
  CHECK(loop.pending() == 4u);
  CHECK(loop.counters().queue_full == 2u);
}

TEST_CASE("encoder ticks stamped at a scan's time are predicted before that scan is applied", "[loop]") {
  RecordingEstimator est;
  Loop loop(est, est::loop::LoopTiming{});
  Outputs out;
  SteadyClock clock;
  float r[1] = {1.0f};
  loop.push(est::loop::WheelTicksInput{0, 0, 0});
  loop.push(est::loop::WheelTicksInput{10 * kMs, 4, 4});
  loop.push(est::loop::WheelTicksInput{20 * kMs, 6, 6});
  loop.push(est::loop::ScanInput{20 * kMs, est::ScanLayout{0.0f, 0.1f, 1, 0.1f, 10.0f}, r});
  loop.flush(clock, out);
  std::int32_t before_scan = 0;
  for (const auto& c : est.calls) {
    if (c.kind == 'c') break;
    before_scan += c.left;
  }
  CHECK(before_scan == 10);  // both increments, the one stamped 20 ms included
  // One output per time: the scan's output stands for the 20 ms prediction tick too.
  for (std::size_t i = 1; i < out.all.size(); ++i) CHECK(out.all[i].t_ns > out.all[i - 1].t_ns);
}

TEST_CASE("after a bus outage the motion up to a scan is taken from the next encoder increment", "[loop]") {
  // Encoders at 100 Hz until 100 ms, then nothing until an increment of 300 ticks stamped 400 ms (the counter kept
  // running during the outage). A scan stamped 250 ms arrives with it: half of that increment happened before it.
  RecordingEstimator est;
  Loop loop(est, est::loop::LoopTiming{});
  Outputs out;
  SteadyClock clock;
  float r[1] = {1.0f};
  for (int i = 0; i <= 10; ++i) {
    loop.push(est::loop::WheelTicksInput{i * 10 * kMs, 10, 10});
    loop.run(clock, out);
  }
  loop.push(est::loop::ScanInput{250 * kMs, est::ScanLayout{0.0f, 0.1f, 1, 0.1f, 10.0f}, r});
  loop.push(est::loop::WheelTicksInput{400 * kMs, 300, 300});
  loop.flush(clock, out);
  std::int32_t before_scan = 0, total = 0;
  bool seen_scan = false;
  for (const auto& c : est.calls) {
    if (c.kind == 'c') seen_scan = true;
    if (c.kind == 'p') {
      total += c.left;
      if (!seen_scan) before_scan += c.left;
    }
  }
  CHECK(before_scan == 110 + 150);  // 11 increments of 10, and (250 - 100) / (400 - 100) of 300
  CHECK(total == 110 + 300);        // the rest after the scan: nothing lost, nothing twice
}

TEST_CASE("the features of a landmark sighting are fused after one prediction to their time, with one output",
          "[loop]") {
  RecordingEstimator est;
  Loop loop(est, est::loop::LoopTiming{});
  Outputs out;
  SteadyClock clock;
  loop.push(est::loop::WheelTicksInput{0, 0, 0});
  loop.push(est::loop::WheelTicksInput{10 * kMs, 4, 4});
  loop.push(est::loop::WheelTicksInput{20 * kMs, 6, 6});
  float r[1] = {1.0f};
  loop.push(est::loop::ScanInput{15 * kMs, est::ScanLayout{0.0f, 0.1f, 1, 0.1f, 10.0f}, r});
  // Three features and a scan at 15 ms, arriving out of order.
  loop.push(est::loop::LandmarkInput{15 * kMs, 3.0f, 0.1f, 0.0f, 2});
  loop.push(est::loop::LandmarkInput{15 * kMs, 2.0f, 0.2f, 0.0f, 0});
  loop.push(est::loop::LandmarkInput{15 * kMs, 4.0f, 0.3f, 0.0f, 1});
  loop.flush(clock, out);
  std::string kinds;
  for (const auto& c : est.calls) kinds += c.kind;
  CHECK(kinds == "ppclllp");  // predictions to 10 and 15 ms, the scan, the features, the prediction to 20 ms
  std::vector<std::int32_t> ids;
  for (const auto& c : est.calls)
    if (c.kind == 'l') ids.push_back(c.left);
  CHECK(ids == std::vector<std::int32_t>{0, 1, 2});  // by id, not by arrival
  std::vector<TimeNs> times;
  for (const auto& o : out.all) times.push_back(o.t_ns);
  CHECK(times == std::vector<TimeNs>{10 * kMs, 15 * kMs, 20 * kMs});  // one output for the 15 ms corrections
  CHECK(loop.counters().corrections == 4u);
}

namespace {
struct ScanOnly : RecordingEstimator {
  static constexpr bool kUsesLandmarks = false;
};
}  // namespace

TEST_CASE("an input kind the filter does not use is counted as unused, not as a fault", "[loop]") {
  ScanOnly est;
  est::loop::FilterLoop<ScanOnly, 64, 8, 2> loop(est, est::loop::LoopTiming{});
  Outputs out;
  SteadyClock clock;
  loop.push(est::loop::WheelTicksInput{0, 0, 0});
  CHECK_FALSE(loop.push(est::loop::LandmarkInput{5 * kMs, 3.0f, 0.1f, 0.0f, 2}));
  loop.push(est::loop::WheelTicksInput{10 * kMs, 1, 1});
  loop.flush(clock, out);
  CHECK(loop.counters().unused == 1u);
  CHECK(loop.counters().rejected == 0u);
  for (const auto& c : est.calls) CHECK(c.kind == 'p');
  REQUIRE(!out.all.empty());
  CHECK((out.all.back().status & (est::loop::status::kInputRejected | est::loop::status::kLandmarkTimeout)) == 0u);
}

TEST_CASE("a filter on landmarks reports stale sightings in the status word", "[loop]") {
  RecordingEstimator est;
  est::loop::LoopTiming timing;
  timing.landmark_timeout_ns = 300 * kMs;
  Loop loop(est, timing);
  Outputs out;
  SteadyClock clock;
  for (int i = 0; i <= 100; ++i) {
    loop.push(est::loop::WheelTicksInput{i * 10 * kMs, 1, 1});
    if (i == 20) loop.push(est::loop::LandmarkInput{i * 10 * kMs, 3.0f, 0.1f, 0.0f, 0});
    loop.run(clock, out);
  }
  loop.flush(clock, out);
  auto status_at = [&](TimeNs t) {
    for (const auto& o : out.all)
      if (o.t_ns == t) return o.status;
    FAIL("no output at " << t);
    return 0u;
  };
  CHECK((status_at(100 * kMs) & est::loop::status::kLandmarkTimeout) != 0u);  // none yet
  CHECK((status_at(200 * kMs) & est::loop::status::kLandmarkTimeout) == 0u);  // the sighting
  CHECK((status_at(500 * kMs) & est::loop::status::kLandmarkTimeout) == 0u);  // 300 ms old: still within the limit
  CHECK((status_at(510 * kMs) & est::loop::status::kLandmarkTimeout) != 0u);
  CHECK(loop.counters().landmark_timeouts == 19u + 50u);  // outputs at 10..190 ms and 510..1000 ms
}
