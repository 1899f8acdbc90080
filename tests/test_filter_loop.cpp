#include <catch2/catch.hpp>
#include <algorithm>
#include <cstdint>
#include <vector>

// The fixed-rate filter loop (est/loop/filter_loop.hpp): order, prediction rate, corrections at their time,
// staleness per input kind, the motion each kind contributes (ticks summed and split, twist time-averaged, odometry
// composed and split), unused kinds, overruns and gaps.
#include "est/loop/filter_loop.hpp"
#include "est/random/xoshiro128.hpp"

namespace {

using est::loop::InputKind;
using est::loop::TimeNs;
constexpr TimeNs kMs = 1000000;

// Two-wheel encoder increments.
est::loop::WheelTicksInput ticks(TimeNs t, std::int32_t left, std::int32_t right) {
  est::loop::WheelTicksInput in;
  in.t_ns = t;
  in.ticks[0] = left;
  in.ticks[1] = right;
  in.wheel_count = 2;
  return in;
}

// Records every call, and integrates ticks into x so outputs depend on the order of calls.
struct RecordingEstimator {
  est::loop::InputKinds inputs() const {
    return InputKind::wheel_ticks | InputKind::steering | InputKind::scan | InputKind::landmark;
  }
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
    calls.push_back({'p', m.dt_s, m.ticks[0], m.ticks[1], m.steering_rad, 0.0f});
    x += 0.001f * static_cast<float>(m.ticks[0] + m.ticks[1]) + 0.5f * m.steering_rad * m.dt_s;
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

using Loop = est::loop::FilterLoopStorage<RecordingEstimator, 64, 8, 2>;

struct Stream {
  std::vector<est::loop::WheelTicksInput> ticks;
  std::vector<est::loop::SteeringInput> steer;
  std::vector<std::pair<TimeNs, float>> scans;
};

Stream make_stream() {
  Stream s;
  for (int i = 1; i <= 100; ++i) s.ticks.push_back(ticks(i * 10 * kMs, i % 7, 2 * (i % 5)));  // 100 Hz encoders
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
    in_left += t.ticks[0];
    in_right += t.ticks[1];
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
  loop.push(ticks(0, 1, 1));
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
      loop.push(ticks(i * 10 * kMs, 3, 4));
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
  loop.push(ticks(0, 0, 0));
  loop.push(ticks(60LL * 1000 * kMs, 5, 5));  // one minute later
  loop.flush(clock, out);
  CHECK(est.calls.size() <= 101u);
  CHECK(est.calls.back().dt_s > 58.0f);
}

TEST_CASE("a full queue drops and counts instead of overwriting", "[loop]") {
  RecordingEstimator est;
  est::loop::FilterLoopStorage<RecordingEstimator, 4, 8, 1> loop(est, est::loop::LoopTiming{});
  for (int i = 0; i < 6; ++i) loop.push(ticks(i * kMs, 1, 1));  // all within the window
  CHECK(loop.pending() == 4u);
  CHECK(loop.counters().queue_full == 2u);
}

TEST_CASE("encoder ticks stamped at a scan's time are predicted before that scan is applied", "[loop]") {
  RecordingEstimator est;
  Loop loop(est, est::loop::LoopTiming{});
  Outputs out;
  SteadyClock clock;
  float r[1] = {1.0f};
  loop.push(ticks(0, 0, 0));
  loop.push(ticks(10 * kMs, 4, 4));
  loop.push(ticks(20 * kMs, 6, 6));
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
    loop.push(ticks(i * 10 * kMs, 10, 10));
    loop.run(clock, out);
  }
  loop.push(est::loop::ScanInput{250 * kMs, est::ScanLayout{0.0f, 0.1f, 1, 0.1f, 10.0f}, r});
  loop.push(ticks(400 * kMs, 300, 300));
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
  loop.push(ticks(0, 0, 0));
  loop.push(ticks(10 * kMs, 4, 4));
  loop.push(ticks(20 * kMs, 6, 6));
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
  est::loop::InputKinds inputs() const { return RecordingEstimator::inputs().without(InputKind::landmark); }
};
}  // namespace

TEST_CASE("an input kind the filter does not use is counted as unused, not as a fault", "[loop]") {
  ScanOnly est;
  est::loop::FilterLoopStorage<ScanOnly, 64, 8, 2> loop(est, est::loop::LoopTiming{});
  Outputs out;
  SteadyClock clock;
  loop.push(ticks(0, 0, 0));
  CHECK_FALSE(loop.push(est::loop::LandmarkInput{5 * kMs, 3.0f, 0.1f, 0.0f, 2}));
  loop.push(ticks(10 * kMs, 1, 1));
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
  timing.staleness[InputKind::landmark] = 300 * kMs;
  Loop loop(est, timing);
  Outputs out;
  SteadyClock clock;
  for (int i = 0; i <= 100; ++i) {
    loop.push(ticks(i * 10 * kMs, 1, 1));
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
  CHECK(loop.counters().of(InputKind::landmark).stale == 19u + 50u);  // outputs at 10..190 ms and 510..1000 ms
  CHECK(loop.counters().of(InputKind::landmark).accepted == 1u);
  CHECK(loop.counters().of(InputKind::wheel_ticks).accepted == 101u);
}

namespace {

// An estimator of a base that reports its twist and its odometry: records each prediction's motion.
struct MotionRecorder {
  est::loop::InputKinds uses = InputKind::twist | InputKind::odometry | InputKind::scan;
  std::vector<est::loop::MotionInput> predictions;
  std::vector<std::size_t> corrections_after;  // predictions made before each correction
  est::loop::InputKinds inputs() const { return uses; }
  est::loop::StepOutcome predict(const est::loop::MotionInput& m) {
    predictions.push_back(m);
    return est::loop::StepOutcome::applied;
  }
  est::loop::StepOutcome correct(const est::loop::ScanInput&) {
    corrections_after.push_back(predictions.size());
    return est::loop::StepOutcome::applied;
  }
  est::PoseEstimate estimate() const { return {}; }
};
using MotionLoop = est::loop::FilterLoopStorage<MotionRecorder, 64, 4, 2>;

est::loop::OdometryInput odometry(TimeNs t, float x, float y, float theta) {
  est::loop::OdometryInput in;
  in.t_ns = t;
  in.increment = {x, y, theta};
  return in;
}

}  // namespace

TEST_CASE("an estimator that uses twist sees each interval's time average: a twist counts for the time it held",
          "[loop][twist]") {
  MotionRecorder est;
  MotionLoop loop(est, est::loop::LoopTiming{});
  Outputs out;
  SteadyClock clock;
  loop.push(est::loop::TwistInput{0, 1.0f, 0.5f, 0.2f});
  loop.push(est::loop::TwistInput{2500000, 3.0f, -0.5f, 0.2f});  // 2.5 ms into the first 10 ms period
  loop.push(est::loop::TwistInput{30 * kMs, 0.0f, 0.0f, 0.0f});
  loop.flush(clock, out);
  REQUIRE(est.predictions.size() == 3u);  // 10, 20, 30 ms
  const est::loop::MotionInput& first = est.predictions[0];
  CHECK(first.twist_known);
  CHECK(first.dt_s == Approx(0.01f));
  CHECK(first.twist.v1_mps == Approx(0.25 * 1.0 + 0.75 * 3.0).epsilon(1e-5));
  CHECK(first.twist.v2_mps == Approx(0.25 * 0.5 - 0.75 * 0.5).epsilon(1e-5));
  CHECK(first.twist.w_rps == Approx(0.2).epsilon(1e-5));
  // Held into the next period whole, then the last sample holds from 30 ms.
  CHECK(est.predictions[1].twist.v1_mps == Approx(3.0).epsilon(1e-5));
  CHECK(est.predictions[2].twist.v1_mps == Approx(3.0).epsilon(1e-5));
  CHECK(loop.counters().of(InputKind::twist).accepted == 3u);
}

TEST_CASE("a twist that changes right before a scan is averaged up to the scan, and the rest after it",
          "[loop][twist]") {
  MotionRecorder est;
  MotionLoop loop(est, est::loop::LoopTiming{});
  Outputs out;
  SteadyClock clock;
  float r[1] = {1.0f};
  loop.push(est::loop::TwistInput{0, 2.0f, 0.0f, 0.0f});
  loop.push(est::loop::TwistInput{4 * kMs, 4.0f, 0.0f, 0.0f});
  loop.push(est::loop::ScanInput{6 * kMs, est::ScanLayout{0.0f, 0.1f, 1, 0.1f, 10.0f}, r});
  loop.push(est::loop::TwistInput{10 * kMs, 4.0f, 0.0f, 0.0f});
  loop.flush(clock, out);
  REQUIRE(est.predictions.size() == 2u);  // to the scan at 6 ms, then to 10 ms
  REQUIRE(est.corrections_after == std::vector<std::size_t>{1u});
  CHECK(est.predictions[0].dt_s == Approx(0.006f));
  CHECK(est.predictions[0].twist.v1_mps == Approx((4.0 * 2.0 + 2.0 * 4.0) / 6.0).epsilon(1e-5));
  CHECK(est.predictions[1].dt_s == Approx(0.004f));
  CHECK(est.predictions[1].twist.v1_mps == Approx(4.0).epsilon(1e-5));
}

TEST_CASE("odometry increments within a period are composed into one", "[loop][odometry]") {
  MotionRecorder est;
  MotionLoop loop(est, est::loop::LoopTiming{});
  Outputs out;
  SteadyClock clock;
  const float q = 0.5f * est::kPi;
  loop.push(odometry(0, 0.0f, 0.0f, 0.0f));
  loop.push(odometry(4 * kMs, 0.1f, 0.0f, q));     // forward, then turn left a quarter
  loop.push(odometry(10 * kMs, 0.2f, 0.0f, 0.0f)); // forward in the turned frame: +y of the start
  loop.flush(clock, out);
  REQUIRE(est.predictions.size() == 1u);
  const est::Pose2& m = est.predictions[0].odometry;
  CHECK(m.x == Approx(0.1).margin(1e-6));
  CHECK(m.y == Approx(0.2).margin(1e-6));
  CHECK(m.theta == Approx(q).margin(1e-6));
  CHECK(loop.counters().of(InputKind::odometry).accepted == 3u);
}

TEST_CASE("an odometry increment spanning a scan is split at the scan's time: share (+) rest = whole",
          "[loop][odometry]") {
  MotionRecorder est;
  MotionLoop loop(est, est::loop::LoopTiming{});
  Outputs out;
  SteadyClock clock;
  float r[1] = {1.0f};
  const est::Pose2 whole{0.3f, 0.1f, 0.4f};
  loop.push(odometry(0, 0.0f, 0.0f, 0.0f));
  loop.push(odometry(10 * kMs, 0.05f, 0.0f, 0.1f));
  loop.push(est::loop::ScanInput{14 * kMs, est::ScanLayout{0.0f, 0.1f, 1, 0.1f, 10.0f}, r});
  loop.push(odometry(20 * kMs, whole.x, whole.y, whole.theta));  // over (10, 20] ms: 40 % of it before the scan
  loop.flush(clock, out);
  REQUIRE(est.predictions.size() == 3u);  // 10 ms, the scan at 14 ms, 20 ms
  REQUIRE(est.corrections_after == std::vector<std::size_t>{2u});
  CHECK(est.predictions[0].odometry.x == Approx(0.05).margin(1e-7));
  const est::Pose2 share = est.predictions[1].odometry;
  const est::Pose2 rest = est.predictions[2].odometry;
  // The share is the increment's first 40 % (linear in time).
  CHECK(share.x == Approx(0.4f * whole.x).margin(1e-6));
  CHECK(share.y == Approx(0.4f * whole.y).margin(1e-6));
  CHECK(share.theta == Approx(0.4f * whole.theta).margin(1e-6));
  // And nothing is lost or counted twice: the share followed by the rest is the whole increment.
  const est::Pose2 again = est::compose(share, rest);
  CHECK(again.x == Approx(whole.x).margin(1e-6));
  CHECK(again.y == Approx(whole.y).margin(1e-6));
  CHECK(again.theta == Approx(whole.theta).margin(1e-6));
  CHECK_FALSE(rest.is_identity());
}

TEST_CASE("twist and odometry that stop raise their own staleness bits and counters, and only while used",
          "[loop][staleness]") {
  MotionRecorder est;
  est::loop::LoopTiming timing;
  timing.staleness[InputKind::twist] = 50 * kMs;
  timing.staleness[InputKind::odometry] = 100 * kMs;
  MotionLoop loop(est, timing);
  Outputs out;
  SteadyClock clock;
  // Both at 100 Hz up to 100 ms, then the twist stops; odometry goes on to 300 ms.
  for (int k = 0; k <= 30; ++k) {
    const TimeNs t = k * 10 * kMs;
    if (k <= 10) loop.push(est::loop::TwistInput{t, 0.5f, 0.0f, 0.0f});
    loop.push(odometry(t, 0.005f, 0.0f, 0.0f));
    loop.run(clock, out);
  }
  loop.flush(clock, out);
  auto status_at = [&](TimeNs t) {
    for (const auto& o : out.all)
      if (o.t_ns == t) return o.status;
    FAIL("no output at " << t);
    return 0u;
  };
  using namespace est::loop::status;
  CHECK((status_at(100 * kMs) & kTwistTimeout) == 0u);
  CHECK((status_at(150 * kMs) & kTwistTimeout) == 0u);  // 50 ms old: at the limit
  CHECK((status_at(160 * kMs) & kTwistTimeout) != 0u);
  CHECK((status_at(300 * kMs) & kTwistTimeout) != 0u);
  for (const auto& o : out.all) {
    CHECK((o.status & kOdometryTimeout) == 0u);  // fresh throughout
    CHECK((o.status & kEncoderTimeout) == 0u);   // wheel ticks are not used: never stale
    CHECK((o.status & kSteeringTimeout) == 0u);
    CHECK((o.status & kLandmarkTimeout) == 0u);
  }
  REQUIRE(out.all.size() == 30u);  // 10 .. 300 ms
  CHECK(loop.counters().of(InputKind::twist).stale == 15u);     // 160 .. 300 ms
  CHECK(loop.counters().of(InputKind::odometry).stale == 0u);
  CHECK(loop.counters().of(InputKind::scan).stale == 30u);      // used, never seen
  CHECK(loop.counters().of(InputKind::wheel_ticks).stale == 0u);
  CHECK(loop.counters().of(InputKind::landmark).stale == 0u);

  // Odometry that stops is stale after its own limit, on the same clock as every kind.
  MotionRecorder est2;
  MotionLoop loop2(est2, timing);
  Outputs out2;
  for (int k = 0; k <= 30; ++k) {
    const TimeNs t = k * 10 * kMs;
    loop2.push(est::loop::TwistInput{t, 0.5f, 0.0f, 0.0f});
    if (k <= 5) loop2.push(odometry(t, 0.005f, 0.0f, 0.0f));
    loop2.run(clock, out2);
  }
  loop2.flush(clock, out2);
  std::uint32_t stale_outputs = 0;
  for (const auto& o : out2.all) {
    const bool stale = (o.status & kOdometryTimeout) != 0u;
    CHECK(stale == (o.t_ns > 150 * kMs));
    CHECK((o.status & kTwistTimeout) == 0u);
    stale_outputs += stale ? 1u : 0u;
  }
  CHECK(loop2.counters().of(InputKind::odometry).stale == stale_outputs);
  CHECK(stale_outputs == 15u);
}

TEST_CASE("inputs of every kind the estimator does not use are counted unused and never reach it", "[loop]") {
  MotionRecorder est;
  est.uses = InputKind::twist;  // a velocity-model base without a rangefinder
  MotionLoop loop(est, est::loop::LoopTiming{});
  Outputs out;
  SteadyClock clock;
  float r[1] = {1.0f};
  CHECK(loop.push(est::loop::TwistInput{0, 0.5f, 0.0f, 0.0f}));
  CHECK_FALSE(loop.push(ticks(0, 1, 1)));
  CHECK_FALSE(loop.push(est::loop::SteeringInput{0, 0.1f}));
  CHECK_FALSE(loop.push(odometry(0, 0.1f, 0.0f, 0.0f)));
  CHECK_FALSE(loop.push(est::loop::ScanInput{0, est::ScanLayout{0.0f, 0.1f, 1, 0.1f, 10.0f}, r}));
  CHECK_FALSE(loop.push(est::loop::LandmarkInput{0, 3.0f, 0.1f, 0.0f, 2}));
  CHECK(loop.push(est::loop::TwistInput{10 * kMs, 0.5f, 0.0f, 0.0f}));
  loop.flush(clock, out);
  CHECK(loop.counters().unused == 5u);
  CHECK(loop.counters().inputs == 2u);
  CHECK(loop.counters().rejected == 0u);
  for (const est::loop::InputKindInfo& k : est::loop::kInputKinds) {
    INFO(k.name);
    CHECK(loop.counters().of(k.kind).accepted == (k.kind == InputKind::twist ? 2u : 0u));
    CHECK(loop.counters().of(k.kind).stale == 0u);
  }
  CHECK(loop.inputs() == est::loop::InputKinds(InputKind::twist));
  CHECK(est.corrections_after.empty());
  REQUIRE(est.predictions.size() == 1u);
  CHECK(est.predictions[0].odometry.is_identity());
  REQUIRE(!out.all.empty());
  CHECK((out.all.back().status & est::loop::status::kMask & ~est::loop::status::kTwistTimeout) == 0u);
}

namespace {
// Says it uses scans and landmarks but can correct with neither: the loop takes the kinds it can apply.
struct PredictOnly {
  est::loop::InputKinds inputs() const { return InputKind::wheel_ticks | InputKind::scan | InputKind::landmark; }
  est::loop::StepOutcome predict(const est::loop::MotionInput&) { return est::loop::StepOutcome::applied; }
  est::PoseEstimate estimate() const { return {}; }
};
}  // namespace

TEST_CASE("a measurement kind the estimator has no correct() for is unused, whatever inputs() claims", "[loop]") {
  PredictOnly est;
  est::loop::FilterLoopStorage<PredictOnly, 8, 4, 1> loop(est, est::loop::LoopTiming{});
  CHECK(loop.inputs() == est::loop::InputKinds(InputKind::wheel_ticks));
  float r[1] = {1.0f};
  CHECK_FALSE(loop.push(est::loop::ScanInput{0, est::ScanLayout{0.0f, 0.1f, 1, 0.1f, 10.0f}, r}));
  CHECK_FALSE(loop.push(est::loop::LandmarkInput{0, 3.0f, 0.1f, 0.0f, 2}));
  CHECK(loop.counters().unused == 2u);
}

TEST_CASE("inputs with equal stamps are applied in the table's order whatever order they arrive in", "[loop]") {
  // Steering (held) stamped with a scan is in the motion predicted to that scan; odometry too. Arriving after the
  // scan within the window changes nothing.
  struct Steered {
    std::vector<std::pair<char, float>> calls;
    est::loop::InputKinds inputs() const { return InputKind::steering | InputKind::odometry | InputKind::scan; }
    est::loop::StepOutcome predict(const est::loop::MotionInput& m) {
      calls.push_back({'p', m.steering_known ? m.steering_rad + m.odometry.x : -1.0f});
      return est::loop::StepOutcome::applied;
    }
    est::loop::StepOutcome correct(const est::loop::ScanInput&) {
      calls.push_back({'c', 0.0f});
      return est::loop::StepOutcome::applied;
    }
    est::PoseEstimate estimate() const { return {}; }
  };
  auto run = [](bool scan_first) {
    Steered est;
    est::loop::FilterLoopStorage<Steered, 16, 4, 1> loop(est, est::loop::LoopTiming{});
    Outputs out;
    SteadyClock clock;
    float r[1] = {1.0f};
    const est::loop::ScanInput scan{5 * kMs, est::ScanLayout{0.0f, 0.1f, 1, 0.1f, 10.0f}, r};
    loop.push(odometry(0, 0.0f, 0.0f, 0.0f));
    if (scan_first) loop.push(scan);
    loop.push(odometry(5 * kMs, 0.25f, 0.0f, 0.0f));
    loop.push(est::loop::SteeringInput{5 * kMs, 0.5f});
    if (!scan_first) loop.push(scan);
    loop.flush(clock, out);
    return est.calls;
  };
  const auto a = run(false), b = run(true);
  REQUIRE(a.size() == 2u);
  CHECK(a[0] == std::make_pair('p', 0.75f));  // steering and odometry stamped 5 ms are in the prediction to 5 ms
  CHECK(a[1].first == 'c');
  CHECK(a == b);
}
