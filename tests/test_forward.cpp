// hal::Forward (hal/forward.hpp): one template that shows every sample of a port to a hook and then hands it on,
// unchanged and in the same order, to the next port of the same kind, for every sensor of that port.
#include <catch2/catch.hpp>

#include <string>
#include <vector>

#include "hal/forward.hpp"

namespace {

// Logs what reaches it, by sample type.
struct RawLog final : hal::PortImplementation<RawLog, hal::SensorPort> {
  std::vector<std::string>* log;
  explicit RawLog(std::vector<std::string>& l) : log(&l) {}
  void handle(const hal::WheelTicks& s) { log->push_back("next wheel_ticks " + std::to_string(s.count[0])); }
  void handle(const hal::SteeringSample& s) { log->push_back("next steering " + std::to_string(s.stamp_ns)); }
  void handle(const hal::TwistSample& s) { log->push_back("next twist " + std::to_string(s.stamp_ns)); }
  void handle(const hal::OdometrySample& s) { log->push_back("next odometry " + std::to_string(s.stamp_ns)); }
  void handle(const hal::RangeScanView& s) { log->push_back("next scan " + std::to_string(s.count)); }
  void handle(const hal::LandmarkSightingView& s) { log->push_back("next landmarks " + std::to_string(s.count)); }
};

struct CheckedLog final : hal::PortImplementation<CheckedLog, hal::ValidatedSensorPort> {
  std::vector<std::string> log;
  void handle(const hal::WheelTickDelta& d) { log.push_back("delta " + std::to_string(d.ticks[1])); }
  void handle(const hal::OdometryDelta& d) { log.push_back("odometry " + std::to_string(d.dt_ns)); }
  template <typename Checked>
  void handle(const Checked&) {
    log.push_back("other");
  }
};

// Names the sample it sees, before the next port does.
struct NameHook {
  std::vector<std::string>* log;
  void operator()(const hal::WheelTicks&) { log->push_back("hook wheel_ticks"); }
  void operator()(const hal::SteeringSample&) { log->push_back("hook steering"); }
  void operator()(const hal::TwistSample&) { log->push_back("hook twist"); }
  void operator()(const hal::OdometrySample&) { log->push_back("hook odometry"); }
  void operator()(const hal::RangeScanView&) { log->push_back("hook scan"); }
  void operator()(const hal::LandmarkSightingView&) { log->push_back("hook landmarks"); }
};

}  // namespace

TEST_CASE("every raw sample goes through the hook, then to the next port, unchanged", "[forward]") {
  std::vector<std::string> log;
  RawLog next(log);
  hal::Forward<hal::SensorPort, NameHook> fwd(next, NameHook{&log});
  hal::SensorPort& port = fwd;  // a backend sees a port like any other
  hal::WheelTicks w;
  w.wheel_count = 2;
  w.count[0] = 77;
  port.on(w);
  port.on(hal::SteeringSample{11, 0.1f});
  port.on(hal::TwistSample{12, 0.5f, 0.0f, 0.0f});
  hal::OdometrySample o;
  o.stamp_ns = 13;
  port.on(o);
  const float r[3] = {1.0f, 2.0f, 3.0f};
  port.on(hal::RangeScanView{14, {}, r, 3});
  const hal::LandmarkFeature f[2] = {};
  port.on(hal::LandmarkSightingView{15, f, 2});
  const std::vector<std::string> want = {
      "hook wheel_ticks", "next wheel_ticks 77", "hook steering", "next steering 11",  "hook twist",
      "next twist 12",    "hook odometry",       "next odometry 13", "hook scan",       "next scan 3",
      "hook landmarks",   "next landmarks 2"};
  CHECK(log == want);
}

TEST_CASE("one generic hook serves every checked sample; forward() deduces it; set_next moves the output",
          "[forward]") {
  CheckedLog first, second;
  int seen = 0;
  hal::TimeNs last_stamp = -1;
  auto counter = hal::forward<hal::ValidatedSensorPort>(first, [&](const auto& s) {
    ++seen;
    last_stamp = s.stamp_ns;
  });
  hal::WheelTickDelta d;
  d.stamp_ns = 5;
  d.ticks[1] = -3;
  counter.on(d);
  hal::OdometryDelta o;
  o.stamp_ns = 6;
  o.dt_ns = 10;
  counter.on(o);
  counter.on(hal::TwistSample{7, 1.0f, 0.0f, 0.0f});
  CHECK(seen == 3);
  CHECK(last_stamp == 7);
  CHECK(first.log == std::vector<std::string>{"delta -3", "odometry 10", "other"});
  counter.set_next(second);
  counter.on(hal::SteeringSample{8, 0.0f});
  CHECK(seen == 4);
  CHECK(first.log.size() == 3u);
  CHECK(second.log == std::vector<std::string>{"other"});
}

TEST_CASE("forwards chain: each hook sees the sample in turn", "[forward]") {
  CheckedLog end;
  std::vector<int> order;
  auto inner = hal::forward<hal::ValidatedSensorPort>(end, [&](const auto&) { order.push_back(2); });
  auto outer = hal::forward<hal::ValidatedSensorPort>(inner, [&](const auto&) { order.push_back(1); });
  outer.on(hal::WheelTickDelta{});
  outer.on(hal::SteeringSample{});
  CHECK(order == std::vector<int>{1, 2, 1, 2});
  CHECK(end.log.size() == 2u);
}
