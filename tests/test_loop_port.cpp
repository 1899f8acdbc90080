// The HAL-to-loop adapter (hal/loop_port.hpp): HAL samples become the loop's inputs exactly, estimates carry the
// loop's bits | the transports' bits and the reject count, transport events are never lost between estimates, what
// the loop cannot take is rejected with a reason, and a non-finite estimate is never published.
#include <catch2/catch.hpp>
#include <cmath>
#include <string>
#include <vector>

#include "est/loop/filter_loop.hpp"
#include "hal/loop_port.hpp"
#include "hal/status_word.hpp"

namespace {

using hal::TimeNs;
constexpr TimeNs kMs = hal::kNsPerMs;

// Records the calls; x integrates the ticks so the output depends on them.
struct FakeEstimator {
  est::loop::InputKinds inputs() const {
    using K = est::loop::InputKind;
    return K::wheel_ticks | K::steering | K::twist | K::odometry | K::scan | K::landmark;
  }
  std::vector<est::loop::MotionInput> predictions;
  std::vector<est::loop::LandmarkInput> features;
  std::vector<est::ScanLayout> scans;
  std::vector<float> first_ranges;
  float x = 0.0f;
  bool poison = false;
  est::loop::StepOutcome predict(const est::loop::MotionInput& m) {
    predictions.push_back(m);
    x += 0.001f * static_cast<float>(m.ticks[0] + m.ticks[1]);
    return est::loop::StepOutcome::applied;
  }
  est::loop::StepOutcome correct(const est::loop::ScanInput& s) {
    scans.push_back(s.layout);
    first_ranges.push_back(s.ranges[0]);
    return est::loop::StepOutcome::applied;
  }
  est::loop::StepOutcome correct(const est::loop::LandmarkInput& z) {
    features.push_back(z);
    return est::loop::StepOutcome::applied;
  }
  est::PoseEstimate estimate() const {
    est::PoseEstimate e;
    e.mean = {poison ? std::nanf("") : x, 1.0f, 0.5f};
    e.covariance = Eigen::Matrix3f::Identity() * 0.01f;
    return e;
  }
};

struct Clock final : hal::Clock {
  TimeNs t = 0;
  TimeNs now_ns() override { return t += 1000; }
};

struct Sink final : hal::EstimateSink {
  std::vector<hal::Estimate> all;
  void publish(const hal::Estimate& e) override { all.push_back(e); }
};

using Port = hal::LoopPort<FakeEstimator>;

struct Rig {
  FakeEstimator est;
  est::loop::FilterLoopStorage<FakeEstimator, 64, 16, 2> loop{est, est::loop::LoopTiming{}};
  Clock clock;
  Sink sink;
  Port port{loop, clock, sink};

  // Encoder samples every 10 ms: after the sample at k * 10 ms, those up to (k - 2) * 10 ms are applied (20 ms
  // reorder window), and the estimate of each 10 ms prediction up to there is out.
  void step(int k) { ticks(k * 10 * kMs, 1, 1); }
  void ticks(TimeNs t, std::int32_t l, std::int32_t r) {
    hal::WheelTickDelta d;
    d.stamp_ns = t;
    d.wheel_count = 2;
    d.ticks[0] = l;
    d.ticks[1] = r;
    port.on(d);
  }
};

// Every loop input a checked sample converts to.
struct Converted {
  std::vector<est::loop::WheelTicksInput> ticks;
  std::vector<est::loop::SteeringInput> steering;
  std::vector<est::loop::TwistInput> twists;
  std::vector<est::loop::OdometryInput> odometry;
  std::vector<est::loop::ScanInput> scans;
  std::vector<est::loop::LandmarkInput> features;
  void operator()(const est::loop::WheelTicksInput& in) { ticks.push_back(in); }
  void operator()(const est::loop::SteeringInput& in) { steering.push_back(in); }
  void operator()(const est::loop::TwistInput& in) { twists.push_back(in); }
  void operator()(const est::loop::OdometryInput& in) { odometry.push_back(in); }
  void operator()(const est::loop::ScanInput& in) { scans.push_back(in); }
  void operator()(const est::loop::LandmarkInput& in) { features.push_back(in); }
};

template <typename Checked>
Converted convert(const Checked& sample) {
  Converted c;
  hal::to_loop_inputs(sample, [&c](const auto& in) { c(in); });
  return c;
}

}  // namespace

TEST_CASE("HAL samples become the loop's inputs exactly", "[loop_port]") {
  hal::WheelTickDelta d;
  d.stamp_ns = 123456789;
  d.dt_ns = 10 * kMs;
  d.wheel_count = 4;
  d.ticks[0] = -70000;
  d.ticks[1] = 2147483647;
  d.ticks[2] = 5;
  d.ticks[3] = -6;
  const Converted wc = convert(d);
  REQUIRE(wc.ticks.size() == 1u);
  const est::loop::WheelTicksInput& w = wc.ticks[0];
  CHECK(w.t_ns == 123456789);
  CHECK(w.wheel_count == 4);
  CHECK(w.ticks[0] == -70000);
  CHECK(w.ticks[1] == 2147483647);
  CHECK(w.ticks[2] == 5);
  CHECK(w.ticks[3] == -6);

  const Converted sc = convert(hal::SteeringSample{42, -0.3125f});
  REQUIRE(sc.steering.size() == 1u);
  CHECK(sc.steering[0].t_ns == 42);
  CHECK(sc.steering[0].angle_rad == -0.3125f);

  const Converted tc = convert(hal::TwistSample{43, 1.25f, -0.5f, 0.75f});
  REQUIRE(tc.twists.size() == 1u);
  CHECK(tc.twists[0].t_ns == 43);
  CHECK(tc.twists[0].v1_mps == 1.25f);
  CHECK(tc.twists[0].v2_mps == -0.5f);
  CHECK(tc.twists[0].w_rps == 0.75f);

  hal::OdometryDelta o;
  o.stamp_ns = 44;
  o.dt_ns = 10 * kMs;
  o.increment = {0.125f, -0.0625f, 0.03125f};
  o.source.pose = {100.0f, 200.0f, 1.0f};  // the pose it came from is the recorder's, not the loop's
  const Converted oc = convert(o);
  REQUIRE(oc.odometry.size() == 1u);
  CHECK(oc.odometry[0].t_ns == 44);
  CHECK(oc.odometry[0].increment.x == 0.125f);
  CHECK(oc.odometry[0].increment.y == -0.0625f);
  CHECK(oc.odometry[0].increment.theta == 0.03125f);

  const float ranges[3] = {1.0f, INFINITY, 0.01f};
  hal::RangeScanView v{77, {-3.1f, 0.0175f, 0.05f, 12.0f, 0.1f}, ranges, 3};
  const Converted rc = convert(v);
  REQUIRE(rc.scans.size() == 1u);
  const est::loop::ScanInput& in = rc.scans[0];
  CHECK(in.t_ns == 77);
  CHECK(in.layout.angle_min == -3.1f);
  CHECK(in.layout.angle_increment == 0.0175f);
  CHECK(in.layout.count == 3);
  CHECK(in.layout.range_min == 0.05f);
  CHECK(in.layout.range_max == 12.0f);
  CHECK(in.ranges == ranges);  // not copied here: the loop's queue copies

  const hal::LandmarkFeature f[2] = {{4.5f, -0.25f, 7.0f, 3}, {2.0f, 0.5f, 1.0f, -1}};
  const Converted lc = convert(hal::LandmarkSightingView{99, f, 2});
  REQUIRE(lc.features.size() == 2u);  // one input per feature, with the sighting's stamp
  const est::loop::LandmarkInput& z = lc.features[0];
  CHECK(z.t_ns == 99);
  CHECK(z.range_m == 4.5f);
  CHECK(z.bearing_rad == -0.25f);
  CHECK(z.signature == 7.0f);
  CHECK(z.id == 3);
  CHECK(lc.features[1].t_ns == 99);
  CHECK(lc.features[1].id == -1);
  CHECK(lc.ticks.empty());
}

TEST_CASE("twists and odometry increments reach the loop through the port, counted by kind", "[loop_port]") {
  Rig r;
  for (int k = 0; k <= 5; ++k) {
    r.port.on(hal::TwistSample{k * 10 * kMs, 0.5f, 0.0f, 0.1f});
    hal::OdometryDelta o;
    o.stamp_ns = k * 10 * kMs;
    o.increment = {0.005f, 0.0f, 0.001f};
    r.port.on(o);
  }
  r.port.flush();
  CHECK(r.port.loop_counters().of(est::loop::InputKind::twist).accepted == 6u);
  CHECK(r.port.loop_counters().of(est::loop::InputKind::odometry).accepted == 6u);
  REQUIRE(!r.est.predictions.empty());
  CHECK(r.est.predictions.back().twist_known);
  CHECK(r.est.predictions.back().twist.v1_mps == Approx(0.5f));
  CHECK(r.est.predictions.back().odometry.x == Approx(0.005f));
}

TEST_CASE("every feature of a sighting reaches the filter, with the sighting's stamp", "[loop_port]") {
  Rig rig;
  rig.step(0);
  const hal::LandmarkFeature f[3] = {{3.0f, 0.1f, 1.0f, 2}, {2.0f, -0.4f, 2.0f, -1}, {5.0f, 1.0f, 3.0f, 0}};
  rig.port.on(hal::LandmarkSightingView{15 * kMs, f, 3});
  for (int k = 1; k <= 5; ++k) rig.step(k);
  REQUIRE(rig.est.features.size() == 3u);
  for (const auto& z : rig.est.features) CHECK(z.t_ns == 15 * kMs);
  // Fused by id (the loop's fixed order), whatever order the sensor listed them in.
  CHECK(rig.est.features[0].id == -1);
  CHECK(rig.est.features[1].id == 0);
  CHECK(rig.est.features[2].id == 2);
  CHECK(rig.est.features[2].range_m == 3.0f);
}

TEST_CASE("the loop runs after every input and every tick reaches a prediction", "[loop_port]") {
  Rig r;
  for (int k = 0; k <= 50; ++k) r.ticks(k * 10 * kMs, 3, 4);
  r.port.flush();
  std::int64_t left = 0, right = 0;
  for (const auto& m : r.est.predictions) {
    left += m.ticks[0];
    right += m.ticks[1];
  }
  // An increment stamped t is motion up to t, so it is in the prediction at t: samples 0..50 all reach the
  // predictions at 10..500 ms (the one stamped 0 joins the first).
  CHECK(left == 51 * 3);
  CHECK(right == 51 * 4);
  REQUIRE(r.sink.all.size() == r.port.published());
  CHECK(r.sink.all.size() == 50u);  // one estimate per 10 ms period
  CHECK(r.sink.all.back().stamp_ns == 500 * kMs);
  CHECK(r.sink.all.back().pose.x == r.est.x);
}

TEST_CASE("an estimate carries the loop's bits, the transports' bits and the reject count", "[loop_port]") {
  Rig r;
  r.port.set_transport_status(hal::status::kCanErrorPassive | hal::status::kCanRxOverflow | 0x3u /* loop bits */);
  r.port.set_upstream_rejects(5);
  for (int k = 0; k <= 3; ++k) r.step(k);  // publishes the estimate at 10 ms
  REQUIRE(r.sink.all.size() == 1u);
  const hal::Estimate& e = r.sink.all[0];
  // The loop's own bits: no steering and no scan yet -> their timeouts; the transports' as given; 0x3 was not
  // the transports' to set and is masked out (the encoder timeout bit is not up: ticks are fresh).
  CHECK((e.status & hal::status::kSteeringTimeout) != 0u);
  CHECK((e.status & hal::status::kScanTimeout) != 0u);
  CHECK((e.status & hal::status::kEncoderTimeout) == 0u);
  CHECK((e.status & hal::status::kCanErrorPassive) != 0u);
  CHECK((e.status & hal::status::kCanRxOverflow) != 0u);
  CHECK(e.rejected_inputs == 5u);
  CHECK((e.status & hal::status::kInputRejected) != 0u);  // 5 rejects since the (absent) previous estimate

  // An event reported once is in the next estimate even if the transport has cleared it by then; then it is gone.
  r.port.set_transport_status(hal::status::kCanProtocolError);
  r.port.set_transport_status(0);
  r.step(4);
  REQUIRE(r.sink.all.size() == 2u);
  CHECK((r.sink.all[1].status & hal::status::kCanProtocolError) != 0u);
  CHECK((r.sink.all[1].status & hal::status::kInputRejected) == 0u);  // no new reject
  r.step(5);
  REQUIRE(r.sink.all.size() == 3u);
  CHECK((r.sink.all[2].status & hal::status::kTransportMask) == 0u);
}

TEST_CASE("what the loop cannot take is rejected with a reason and counted", "[loop_port]") {
  // (How many wheels a sample has is the validator's and the model's control assembler's to judge, not the port's.)
  Rig r;
  float ranges[17] = {};
  r.port.on(hal::RangeScanView{0, {0.0f, 0.1f, 0.05f, 10.0f, 0.1f}, ranges, 17});  // capacity is 16
  r.port.on(hal::RangeScanView{0, {0.0f, 0.1f, 0.05f, 10.0f, 0.1f}, ranges, 0});
  CHECK(r.port.rejects()[hal::LoopPortReject::scan_too_large] == 2u);
  CHECK(r.port.rejected_inputs() == 2u);
  CHECK(r.port.loop_counters().inputs == 0u);
  CHECK(std::string(hal::to_string(hal::LoopPortReject::scan_too_large)) == "scan_too_large");

  ranges[0] = 2.5f;
  r.ticks(0, 0, 0);
  r.port.on(hal::RangeScanView{5 * kMs, {0.0f, 0.1f, 0.05f, 10.0f, 0.1f}, ranges, 16});
  r.port.flush();
  REQUIRE(r.est.scans.size() == 1u);
  CHECK(r.est.scans[0].count == 16);
  CHECK(r.est.first_ranges[0] == 2.5f);
}

TEST_CASE("a non-finite estimate is never published: the last good pose is held and flagged", "[loop_port]") {
  Rig r;
  for (int k = 0; k <= 3; ++k) r.step(k);
  REQUIRE(r.sink.all.size() == 1u);
  const hal::Estimate good = r.sink.all[0];
  r.est.poison = true;
  r.step(4);
  REQUIRE(r.sink.all.size() == 2u);
  const hal::Estimate& held = r.sink.all[1];
  CHECK(held.pose.x == good.pose.x);
  CHECK(held.pose.y == good.pose.y);
  CHECK(held.covariance == good.covariance);
  CHECK((held.status & hal::status::kFilterDegenerate) != 0u);
  CHECK(r.port.nonfinite_estimates() == 1u);
}
