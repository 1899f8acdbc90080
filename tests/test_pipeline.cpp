// hal::Pipeline (hal/pipeline.hpp), the one composition of the HAL gate, a tap, the loop port, the filter loop and
// the estimate sink: raw samples in, estimates out at the loop's rate; every reject (the gate's, the transports',
// the port's) totalled in the estimates; a tap sees exactly what reaches the loop.
#include <catch2/catch.hpp>

#include <cmath>
#include <vector>

#include "est/loop/filter_loop.hpp"
#include "hal/forward.hpp"
#include "hal/pipeline.hpp"
#include "hal/status_word.hpp"

namespace {

using est::loop::InputKind;
using hal::kNsPerMs;
using hal::TimeNs;

// A base on its twist with a rangefinder: integrates v1 into x.
struct TwistEstimator {
  std::vector<est::loop::MotionInput> predictions;
  int scans = 0;
  float x = 0.0f;
  est::loop::InputKinds inputs() const { return InputKind::twist | InputKind::scan; }
  est::loop::StepOutcome predict(const est::loop::MotionInput& m) {
    predictions.push_back(m);
    x += m.twist.v1_mps * m.dt_s;
    return est::loop::StepOutcome::applied;
  }
  est::loop::StepOutcome correct(const est::loop::ScanInput&) {
    ++scans;
    return est::loop::StepOutcome::applied;
  }
  est::PoseEstimate estimate() const {
    est::PoseEstimate e;
    e.mean = {x, 0.0f, 0.0f};
    e.covariance = Eigen::Matrix3f::Identity() * 0.01f;
    return e;
  }
};

struct ManualClock final : hal::Clock {
  TimeNs now = 0;
  TimeNs now_ns() override { return now; }
};
struct StepClock final : hal::Clock {
  TimeNs t = 0;
  TimeNs now_ns() override { return t += 1000; }
};
struct Sink final : hal::EstimateSink {
  std::vector<hal::Estimate> all;
  void publish(const hal::Estimate& e) override { all.push_back(e); }
};

struct Rig {
  TwistEstimator est;
  est::loop::FilterLoopStorage<TwistEstimator, 32, 8, 1> loop{est, est::loop::LoopTiming{}};
  ManualClock samples;
  StepClock steps;
  Sink sink;
  hal::Pipeline<TwistEstimator> pipeline{loop, limits(), samples, steps, sink};

  static hal::InputLimits limits() {
    hal::InputLimits l;
    l.scan.min_valid_beams = 1;
    return l;
  }
  void twist(TimeNs t, float v1) {
    samples.now = t;
    pipeline.input().on(hal::TwistSample{t, v1, 0.0f, 0.0f});
  }
};

}  // namespace

TEST_CASE("raw samples in, estimates out: the loop's outputs at its rate, its pose, its stamps", "[pipeline]") {
  Rig r;
  for (int k = 0; k <= 50; ++k) r.twist(k * 10 * kNsPerMs, 1.0f);
  r.pipeline.flush();
  REQUIRE(r.sink.all.size() == 50u);  // 10 .. 500 ms
  CHECK(r.sink.all.front().stamp_ns == 10 * kNsPerMs);
  CHECK(r.sink.all.back().stamp_ns == 500 * kNsPerMs);
  CHECK(r.sink.all.back().pose.x == Approx(0.5f));  // 1 m/s for 0.5 s
  CHECK(r.pipeline.port().published() == 50u);
  CHECK(r.pipeline.loop().counters().of(InputKind::twist).accepted == 51u);
  CHECK(r.pipeline.gate().faults().total() == 0u);
  for (const hal::Estimate& e : r.sink.all) CHECK(e.rejected_inputs == 0u);
}

TEST_CASE("rejects anywhere are totalled in the estimates: the gate's, the transports', the port's", "[pipeline]") {
  Rig r;
  r.twist(0, 1.0f);
  r.twist(10 * kNsPerMs, std::nanf(""));  // the gate: not finite
  r.twist(10 * kNsPerMs, 1.0f);
  r.twist(5 * kNsPerMs, 1.0f);            // the gate: time backwards
  r.pipeline.refresh(hal::status::kCanErrorWarning, 3);  // a transport: 3 frames rejected, and a bit
  float ranges[9] = {1, 1, 1, 1, 1, 1, 1, 1, 1};
  r.samples.now = 20 * kNsPerMs;
  r.pipeline.input().on(hal::RangeScanView{20 * kNsPerMs, {0.0f, 0.1f, 0.1f, 10.0f, 0.1f}, ranges, 9});  // > 8 beams
  for (int k = 2; k <= 10; ++k) {
    r.pipeline.refresh(0, 3);
    r.twist(k * 10 * kNsPerMs, 1.0f);
  }
  r.pipeline.flush();
  REQUIRE(!r.sink.all.empty());
  CHECK(r.pipeline.gate().faults().total() == 2u);
  CHECK(r.pipeline.port().rejects()[hal::LoopPortReject::scan_too_large] == 1u);
  CHECK(r.sink.all.back().rejected_inputs == 2u + 3u + 1u);
  CHECK(r.pipeline.port().rejected_inputs() == 6u);
  // The first estimate after the rejects says so, and carries the transport's bit; the last ones are clear.
  CHECK((r.sink.all.front().status & hal::status::kInputRejected) != 0u);
  CHECK((r.sink.all.front().status & hal::status::kCanErrorWarning) != 0u);
  CHECK((r.sink.all.back().status & hal::status::kInputRejected) == 0u);
  CHECK((r.sink.all.back().status & hal::status::kCanErrorWarning) == 0u);
  CHECK(r.est.scans == 0);
}

TEST_CASE("a tap sees every checked sample that reaches the loop and nothing the gate refused", "[pipeline]") {
  Rig r;
  std::vector<TimeNs> tapped;
  auto tap = hal::forward<hal::ValidatedSensorPort>(r.pipeline.adapter(),
                                                    [&](const auto& s) { tapped.push_back(s.stamp_ns); });
  r.pipeline.set_tap(tap);
  r.twist(0, 1.0f);
  r.twist(10 * kNsPerMs, 50.0f);  // beyond the base's 5 m/s: refused at the gate
  r.twist(20 * kNsPerMs, 1.0f);
  float ranges[4] = {1, 1, 1, 1};
  r.samples.now = 25 * kNsPerMs;
  r.pipeline.input().on(hal::RangeScanView{25 * kNsPerMs, {0.0f, 0.1f, 0.1f, 10.0f, 0.1f}, ranges, 4});
  r.twist(60 * kNsPerMs, 1.0f);
  r.pipeline.flush();
  CHECK(tapped == std::vector<TimeNs>{0, 20 * kNsPerMs, 25 * kNsPerMs, 60 * kNsPerMs});
  CHECK(r.pipeline.loop().counters().inputs == 4u);
  CHECK(r.est.scans == 1);
  CHECK(r.pipeline.gate().twist().faults()[hal::Fault::out_of_range] == 1u);
}

TEST_CASE("the sample clock judges staleness, the step clock only times the steps", "[pipeline]") {
  Rig r;
  r.samples.now = 1000 * kNsPerMs;
  r.pipeline.input().on(hal::TwistSample{500 * kNsPerMs, 1.0f, 0.0f, 0.0f});  // 500 ms old on arrival
  CHECK(r.pipeline.gate().twist().faults()[hal::Fault::stale] == 1u);
  for (int k = 0; k <= 5; ++k) r.twist(1000 * kNsPerMs + k * 10 * kNsPerMs, 1.0f);
  r.pipeline.flush();
  CHECK(r.pipeline.loop().counters().worst_step_ns == 1000);  // one StepClock tick per step
  CHECK(r.pipeline.loop().counters().overruns == 0u);
}
