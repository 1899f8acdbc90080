// LCM over UDP multicast between two LCM instances, as two processes on a robot would talk. ctest runs it in an
// isolated network namespace (unshare -n, loopback multicast routed), so it neither needs nor disturbs a network.
#include <catch2/catch.hpp>
#include <chrono>
#include <vector>

#include "hal/lcm/lcm_backend.hpp"

namespace {
const char* kUrl = "udpm://239.255.76.67:7667?ttl=0";

struct Recorder final : hal::PortImplementation<Recorder, hal::SensorPort> {
  std::vector<hal::SteeringSample> steering;
  std::vector<hal::TwistSample> twists;
  std::vector<std::size_t> scans;
  int other = 0;
  void handle(const hal::SteeringSample& s) { steering.push_back(s); }
  void handle(const hal::TwistSample& s) { twists.push_back(s); }
  void handle(const hal::RangeScanView& s) { scans.push_back(s.count); }
  template <typename Raw>
  void handle(const Raw&) {
    ++other;
  }
};
}  // namespace

TEST_CASE("sensor messages and estimates cross udpm between two LCM instances", "[lcm][udpm]") {
  lcm::LCM sensors(kUrl);
  lcm::LCM estimator(kUrl);
  REQUIRE(sensors.good());
  REQUIRE(estimator.good());
  Recorder port;
  hal::lcm::LcmInputs in(estimator, {}, port);
  hal::lcm::LcmOutputs out(estimator, {});

  std::vector<est_lcm::pose_estimate_t> poses;
  struct Handler {
    std::vector<est_lcm::pose_estimate_t>* poses;
    void on(const lcm::ReceiveBuffer*, const std::string&, const est_lcm::pose_estimate_t* m) { poses->push_back(*m); }
  } h{&poses};
  sensors.subscribe("EST_POSE", &Handler::on, &h);

  est_lcm::range_scan_t scan{};
  scan.ranges_m.assign(1081, 5.0f);  // 4.3 kB: more than one UDP fragment of LCM's
  scan.num_ranges = 1081;
  // Multicast needs the subscriptions in place before anything is sent: send until received (bounded).
  for (int attempt = 0; attempt < 50 && (port.steering.empty() || port.scans.empty() || port.twists.empty());
       ++attempt) {
    const est_lcm::steering_t s = hal::lcm::to_lcm(hal::SteeringSample{attempt, 0.2f});
    sensors.publish("EST_STEERING", &s);
    sensors.publish("EST_RANGE_SCAN", &scan);
    const est_lcm::twist_t t = hal::lcm::to_lcm(hal::TwistSample{attempt, 0.5f, -0.1f, 0.3f});
    sensors.publish("EST_TWIST", &t);
    while (estimator.handleTimeout(20) > 0) {
    }
  }
  REQUIRE(!port.steering.empty());
  CHECK(port.steering.back().angle_rad == 0.2f);
  REQUIRE(!port.scans.empty());
  CHECK(port.scans.back() == 1081);
  REQUIRE(!port.twists.empty());
  CHECK(port.twists.back().v1_mps == 0.5f);
  CHECK(port.twists.back().w_rps == 0.3f);
  CHECK(port.other == 0);

  hal::Estimate e;
  e.pose = {3.0f, 4.0f, 0.5f};
  for (int attempt = 0; attempt < 50 && poses.empty(); ++attempt) {
    out.publish(e);
    while (sensors.handleTimeout(20) > 0) {
    }
  }
  REQUIRE(!poses.empty());
  CHECK(poses[0].x_m == 3.0f);
  CHECK(in.rejects().total() == 0);
}
