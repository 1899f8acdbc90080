// LCM backend over memq:// (in process): every input kind reaches the SensorPort on configurable channels, every
// output can be read back, and malformed, mis-shaped or bad-valued messages are rejected with their reason counted;
// the twist and odometry conversions round-trip and decode only through the guard; team messages go out on the team
// channel and come in through the team validator.
#include <catch2/catch.hpp>
#include <cmath>
#include <cstring>
#include <limits>
#include <vector>

#include "hal/lcm/lcm_backend.hpp"
#include "hal/status_word.hpp"
#include "hal/validated_inputs.hpp"

using hal::lcm::LcmReject;

namespace {

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();

struct Recorder final : hal::PortImplementation<Recorder, hal::SensorPort>, hal::TeamPort {
  std::vector<hal::WheelTicks> wheels;
  std::vector<hal::SteeringSample> steering;
  std::vector<hal::TwistSample> twists;
  std::vector<hal::OdometrySample> odometry;
  std::vector<std::vector<float>> scans;
  std::vector<hal::ScanGeometry> geometry;
  std::vector<est::team::TeamMessage> team;
  std::vector<std::vector<hal::LandmarkFeature>> sightings;
  std::vector<hal::TimeNs> sighting_stamps;
  void handle(const hal::WheelTicks& s) { wheels.push_back(s); }
  void handle(const hal::SteeringSample& s) { steering.push_back(s); }
  void handle(const hal::TwistSample& s) { twists.push_back(s); }
  void handle(const hal::OdometrySample& s) { odometry.push_back(s); }
  void handle(const hal::RangeScanView& s) {
    scans.emplace_back(s.ranges, s.ranges + s.count);
    geometry.push_back(s.geometry);
  }
  void handle(const hal::LandmarkSightingView& s) {
    sightings.emplace_back(s.features, s.features + s.count);
    sighting_stamps.push_back(s.stamp_ns);
  }
  void on_team_message(const est::team::TeamMessage& m) override { team.push_back(m); }
};

// Counts the checked samples that pass the gate.
struct CheckedCounter final : hal::PortImplementation<CheckedCounter, hal::ValidatedSensorPort> {
  int n = 0;
  template <typename Checked>
  void handle(const Checked&) {
    ++n;
  }
};

void pump(lcm::LCM& lcm) {
  while (lcm.handleTimeout(0) > 0) {
  }
}

hal::lcm::InputConfig custom_channels() {
  hal::lcm::InputConfig c;
  c.channels.wheel_ticks = "ROBOT7/ODOM_TICKS";
  c.channels.steering = "ROBOT7/STEER";
  c.channels.range_scan = "ROBOT7/LIDAR";
  c.channels.team = "TEAM";
  c.channels.landmarks = "ROBOT7/MARKERS";
  c.channels.twist = "ROBOT7/CMD_VEL";
  c.channels.odometry = "ROBOT7/ODOM";
  c.wheel_counter_bits = 16;
  c.max_ranges = 1081;
  return c;
}

template <typename M>
std::vector<std::uint8_t> bytes_of(const M& m) {
  std::vector<std::uint8_t> b(static_cast<std::size_t>(m.getEncodedSize()));
  REQUIRE(m.encode(b.data(), 0, static_cast<int>(b.size())) == static_cast<int>(b.size()));
  return b;
}

est_lcm::range_scan_t small_scan() {
  est_lcm::range_scan_t s;
  s.stamp_ns = 1000;
  s.angle_min_rad = -1.0f;
  s.angle_increment_rad = 0.5f;
  s.range_min_m = 0.1f;
  s.range_max_m = 20.0f;
  s.scan_time_s = 0.1f;
  s.ranges_m = {1.0f, std::numeric_limits<float>::infinity(), kNaN, 3.5f, 19.0f};
  s.num_ranges = 5;
  return s;
}

}  // namespace

TEST_CASE("sensor inputs on configured channels reach the SensorPort as HAL samples", "[lcm]") {
  lcm::LCM lcm("memq://");
  REQUIRE(lcm.good());
  Recorder port;
  hal::lcm::LcmInputs in(lcm, custom_channels(), port);
  hal::team::TeamValidator validator(4, 0);
  in.subscribe_team(port, validator);

  hal::WheelTicks w;
  w.stamp_ns = 500;
  w.wheel_count = 2;
  w.count[0] = 65535;
  w.count[1] = 7;
  const est_lcm::encoder_ticks_t ticks = hal::lcm::to_lcm(w, 16);
  lcm.publish("ROBOT7/ODOM_TICKS", &ticks);
  const est_lcm::steering_t steer = hal::lcm::to_lcm(hal::SteeringSample{600, -0.3f});
  lcm.publish("ROBOT7/STEER", &steer);
  const est_lcm::range_scan_t scan = small_scan();
  lcm.publish("ROBOT7/LIDAR", &scan);
  est::team::TeamMessage t;
  t.stamp_ns = 700;
  t.robot = 3;
  t.seq = 7;
  t.control.kind = est::team::ControlKind::velocity;
  t.control.v1 = 0.5f;
  t.control.w = -0.1f;
  t.control.dt_s = 0.1f;
  t.count = 2;
  t.measurements[0] = {est::team::TargetKind::landmark, true, 4.0f, 0.5f, 12};
  t.measurements[1] = {est::team::TargetKind::robot, false, 2.5f, 0.0f, 1};
  const est_lcm::team_message_t team = hal::lcm::to_lcm(t);
  lcm.publish("TEAM", &team);
  const hal::LandmarkFeature features[2] = {{4.0f, 0.5f, 12.0f, 3}, {2.5f, -1.0f, 0.25f, -1}};
  const est_lcm::landmark_sighting_t markers = hal::lcm::to_lcm(hal::LandmarkSightingView{800, features, 2});
  lcm.publish("ROBOT7/MARKERS", &markers);
  lcm.publish("EST_STEERING", &steer);  // the default name is not subscribed any more
  pump(lcm);

  REQUIRE(port.wheels.size() == 1);
  CHECK(port.wheels[0].stamp_ns == 500);
  CHECK(port.wheels[0].count[0] == 65535);
  CHECK(port.wheels[0].count[1] == 7);
  REQUIRE(port.steering.size() == 1);
  CHECK(port.steering[0].angle_rad == -0.3f);
  REQUIRE(port.scans.size() == 1);
  CHECK(port.scans[0].size() == 5);
  CHECK(std::isinf(port.scans[0][1]));
  CHECK(std::isnan(port.scans[0][2]));
  CHECK(port.geometry[0].range_max_m == 20.0f);
  REQUIRE(port.team.size() == 1);
  CHECK(port.team[0].robot == 3);
  CHECK(port.team[0].seq == 7);
  CHECK(port.team[0].count == 2);
  CHECK(port.team[0].measurements[1].target == est::team::TargetKind::robot);
  CHECK_FALSE(port.team[0].measurements[1].has_bearing);
  CHECK(port.team[0].measurements[0].id == 12);
  REQUIRE(port.sightings.size() == 1);
  CHECK(port.sighting_stamps[0] == 800);
  REQUIRE(port.sightings[0].size() == 2);
  CHECK(port.sightings[0][0].range_m == 4.0f);
  CHECK(port.sightings[0][0].id == 3);
  CHECK(port.sightings[0][1].bearing_rad == -1.0f);
  CHECK(port.sightings[0][1].signature == 0.25f);
  CHECK(port.sightings[0][1].id == -1);
  CHECK(in.accepted() == 4);  // the sensor samples
  CHECK(in.rejects().total() == 0);
  CHECK(validator.accepted() == 1);
  CHECK(in.team_rejects().total() == 0);
}

TEST_CASE("estimates, status, particles and ground truth are published and read back", "[lcm]") {
  lcm::LCM lcm("memq://");
  hal::lcm::Channels ch;
  ch.pose = "OUT/POSE";
  hal::lcm::LcmOutputs out(lcm, ch);

  std::vector<est_lcm::pose_estimate_t> poses;
  std::vector<est_lcm::particle_cloud_t> clouds;
  std::vector<est_lcm::status_t> statuses;
  std::vector<est_lcm::ground_truth_t> truths;
  struct Handler {
    std::vector<est_lcm::pose_estimate_t>* poses;
    std::vector<est_lcm::particle_cloud_t>* clouds;
    std::vector<est_lcm::status_t>* statuses;
    std::vector<est_lcm::ground_truth_t>* truths;
    void pose(const lcm::ReceiveBuffer*, const std::string&, const est_lcm::pose_estimate_t* m) { poses->push_back(*m); }
    void cloud(const lcm::ReceiveBuffer*, const std::string&, const est_lcm::particle_cloud_t* m) { clouds->push_back(*m); }
    void status(const lcm::ReceiveBuffer*, const std::string&, const est_lcm::status_t* m) { statuses->push_back(*m); }
    void truth(const lcm::ReceiveBuffer*, const std::string&, const est_lcm::ground_truth_t* m) { truths->push_back(*m); }
  } h{&poses, &clouds, &statuses, &truths};
  lcm.subscribe("OUT/POSE", &Handler::pose, &h);
  lcm.subscribe("EST_PARTICLES", &Handler::cloud, &h);
  lcm.subscribe("EST_STATUS", &Handler::status, &h);
  lcm.subscribe("EST_GROUND_TRUTH", &Handler::truth, &h);

  hal::Estimate e;
  e.stamp_ns = 123456789;
  e.pose = {1.0f, 2.0f, -0.5f};
  e.covariance << 0.1f, 0.01f, 0.0f, 0.01f, 0.2f, 0.0f, 0.0f, 0.0f, 0.05f;
  e.status = hal::status::kCanLinkDown | hal::status::kFilterDegenerate;
  e.rejected_inputs = 9;
  out.publish(e);
  const float x[10] = {0, 1, 2, 3, 4, 5, 6, 7, 8, 9};
  const float w[10] = {0.1f, 0.1f, 0.1f, 0.1f, 0.1f, 0.1f, 0.1f, 0.1f, 0.1f, 0.1f};
  out.publish_particles(5, x, x, x, w, 10, 3);
  est_lcm::status_t st{};
  st.num_input_faults = static_cast<std::int16_t>(hal::kFaultCount);
  st.input_faults.assign(hal::kFaultCount, 0);
  st.input_faults[static_cast<std::size_t>(hal::Fault::stale)] = 4;
  st.status_word = static_cast<std::int32_t>(e.status);
  out.publish_status(st);
  est_lcm::ground_truth_t gt{};
  gt.x_m = 1.25f;
  out.publish_ground_truth(gt);
  pump(lcm);

  REQUIRE(poses.size() == 1);
  const hal::Estimate back = hal::lcm::to_hal(poses[0]);
  CHECK(back.stamp_ns == e.stamp_ns);
  CHECK(back.pose.theta == -0.5f);
  CHECK(back.covariance == e.covariance);
  CHECK(poses[0].covariance[1] == 0.01f);  // row-major
  CHECK(back.status == e.status);
  CHECK(back.rejected_inputs == 9);
  REQUIRE(clouds.size() == 1);
  CHECK(clouds[0].num_particles == 4);  // particles 0, 3, 6, 9
  CHECK(clouds[0].x_m[3] == 9.0f);
  CHECK(clouds[0].num_total == 10);
  REQUIRE(statuses.size() == 1);
  CHECK(statuses[0].input_faults[static_cast<std::size_t>(hal::Fault::stale)] == 4);
  REQUIRE(truths.size() == 1);
  CHECK(truths[0].x_m == 1.25f);
  CHECK(out.publish_failures() == 0);
}

TEST_CASE("garbage, truncated and wrong-type payloads are malformed; bad counts and shapes are rejected",
          "[lcm]") {
  lcm::LCM lcm("memq://");
  Recorder port;
  hal::lcm::LcmInputs in(lcm, custom_channels(), port);
  hal::team::TeamValidator validator(4, 0);
  in.subscribe_team(port, validator);

  const std::uint8_t garbage[5] = {1, 2, 3, 4, 5};
  lcm.publish("ROBOT7/STEER", garbage, sizeof garbage);
  std::vector<std::uint8_t> scan = bytes_of(small_scan());
  lcm.publish("ROBOT7/LIDAR", scan.data(), static_cast<unsigned>(scan.size() - 3));  // truncated
  const est_lcm::steering_t steer{};
  lcm.publish("ROBOT7/LIDAR", &steer);  // another type: fingerprint mismatch
  CHECK(in.rejects()[LcmReject::malformed] == 0);
  pump(lcm);
  CHECK(in.rejects()[LcmReject::malformed] == 3);

  // The leading count: negative, and larger than the receiver holds (checked before anything is allocated).
  for (std::int32_t n : {-1, 2000, 0x7fffffff}) {
    std::vector<std::uint8_t> b = scan;
    for (int i = 0; i < 4; ++i) b[8 + static_cast<std::size_t>(i)] = static_cast<std::uint8_t>(static_cast<std::uint32_t>(n) >> (24 - 8 * i));
    lcm.publish("ROBOT7/LIDAR", b.data(), static_cast<unsigned>(b.size()));
  }
  hal::WheelTicks five;
  five.wheel_count = 4;
  est_lcm::encoder_ticks_t ticks = hal::lcm::to_lcm(five, 16);
  ticks.num_wheels = 5;
  ticks.count.push_back(0);
  lcm.publish("ROBOT7/ODOM_TICKS", &ticks);
  hal::LandmarkFeature many[hal::kMaxLandmarkFeatures + 1] = {};
  std::vector<std::uint8_t> too_many = bytes_of(hal::lcm::to_lcm(hal::LandmarkSightingView{1, many, 3}));
  too_many[8] = 0;
  too_many[9] = static_cast<std::uint8_t>(hal::kMaxLandmarkFeatures + 1);  // above what the receiver holds
  lcm.publish("ROBOT7/MARKERS", too_many.data(), static_cast<unsigned>(too_many.size()));
  too_many[8] = 0xff;
  too_many[9] = 0xff;  // -1
  lcm.publish("ROBOT7/MARKERS", too_many.data(), static_cast<unsigned>(too_many.size()));
  pump(lcm);
  CHECK(in.rejects()[LcmReject::bad_count] == 6);

  ticks = hal::lcm::to_lcm(five, 32);  // a 32-bit counter where 16 bits are configured
  lcm.publish("ROBOT7/ODOM_TICKS", &ticks);
  // Team payloads: what does not decode is the backend's to count, what decodes the validator's.
  est::team::TeamMessage t;
  t.robot = 1;
  t.count = 1;
  t.measurements[0] = {est::team::TargetKind::landmark, false, 1.0f, 0.0f, 1};
  est_lcm::team_message_t team = hal::lcm::to_lcm(t);
  lcm.publish("TEAM", garbage, sizeof garbage);
  team.measurements[0].has_bearing = 2;
  lcm.publish("TEAM", &team);
  team.measurements[0].has_bearing = 0;
  team.measurements[0].target = 7;
  lcm.publish("TEAM", &team);
  team.measurements[0].target = est_lcm::team_measurement_t::LANDMARK;
  team.measurements[0].range_m = kNaN;
  lcm.publish("TEAM", &team);
  team.measurements[0].range_m = -1.0f;
  lcm.publish("TEAM", &team);
  pump(lcm);
  CHECK(in.rejects()[LcmReject::bad_shape] == 1);
  CHECK(in.rejects()[LcmReject::bad_value] == 0);
  CHECK(in.team_rejects()[LcmReject::malformed] == 1);
  CHECK(in.team_rejects()[LcmReject::bad_shape] == 1);
  CHECK(validator.counts()[est::team::TeamReject::malformed] == 3);
  CHECK(validator.rejected() == 3);
  CHECK(port.wheels.empty());
  CHECK(port.steering.empty());
  CHECK(port.scans.empty());
  CHECK(port.team.empty());
  CHECK(port.sightings.empty());
}

TEST_CASE("a negative count after the first array of status_t is malformed, not a crash", "[lcm]") {
  est_lcm::status_t st{};
  st.num_input_faults = 1;
  st.input_faults = {3};
  st.num_can_frame_rejects = 0;
  st.num_can_scan_rejects = 0;
  std::vector<std::uint8_t> b = bytes_of(st);
  // num_can_frame_rejects sits after hash(8) + count(2) + stamp(8) + word(4) + steps(8) + overruns(8) + 1 x 8.
  const std::size_t at = 8 + 2 + 8 + 4 + 8 + 8 + 8;
  b[at] = 0xFF;
  b[at + 1] = 0xFF;
  est_lcm::status_t out;
  CHECK(hal::lcm::decode_guarded(b.data(), b.size(), out, 64) == LcmReject::malformed);
  std::vector<std::uint8_t> good = bytes_of(st);
  CHECK(hal::lcm::decode_guarded(good.data(), good.size(), out, 64) == LcmReject::none);
  CHECK(out.input_faults[0] == 3);
}

TEST_CASE("through the HAL gate: NaN steering, a NaN scan geometry and time going backwards are counted",
          "[lcm]") {
  struct Clock final : hal::Clock {
    hal::TimeNs now_ns() override { return 1000; }
  } clock;
  CheckedCounter sink;
  hal::InputLimits limits;
  limits.scan.min_valid_beams = 1;
  hal::ValidatedInputs gate(limits, clock, sink);
  lcm::LCM lcm("memq://");
  hal::lcm::LcmInputs in(lcm, custom_channels(), gate);

  est_lcm::steering_t s = hal::lcm::to_lcm(hal::SteeringSample{1000, kNaN});
  lcm.publish("ROBOT7/STEER", &s);
  s.angle_rad = 0.1f;
  lcm.publish("ROBOT7/STEER", &s);
  s.stamp_ns = 999;
  lcm.publish("ROBOT7/STEER", &s);
  est_lcm::range_scan_t scan = small_scan();
  scan.angle_increment_rad = kNaN;
  lcm.publish("ROBOT7/LIDAR", &scan);
  pump(lcm);
  CHECK(in.rejects().total() == 0);  // well-formed LCM: the HAL judges the values
  CHECK(gate.faults()[hal::Fault::not_finite] == 2);
  CHECK(gate.faults()[hal::Fault::time_backwards] == 1);
  CHECK(sink.n == 1);
}

TEST_CASE("twists and odometry poses on their channels reach the SensorPort; their conversions round-trip",
          "[lcm]") {
  lcm::LCM lcm("memq://");
  Recorder port;
  hal::lcm::LcmInputs in(lcm, custom_channels(), port);
  CHECK(in.is_input_channel("ROBOT7/CMD_VEL"));
  CHECK(in.is_input_channel("ROBOT7/ODOM"));
  CHECK_FALSE(in.is_input_channel("EST_TWIST"));  // renamed: the default is not subscribed
  CHECK_FALSE(in.is_input_channel("TEAM"));       // the team channel is not a sensor's

  const est_lcm::twist_t twist = hal::lcm::to_lcm(hal::TwistSample{900, 1.5f, -0.25f, 0.125f});
  CHECK(twist.stamp_ns == 900);
  CHECK(twist.v2_mps == -0.25f);
  lcm.publish("ROBOT7/CMD_VEL", &twist);
  lcm.publish("EST_TWIST", &twist);
  hal::OdometrySample o;
  o.stamp_ns = 950;
  o.pose = {12.5f, -3.25f, 2.5f};
  o.wrap_m = 262.144f;  // LCM's floats do not wrap: not carried
  const est_lcm::odometry_t odom = hal::lcm::to_lcm(o);
  CHECK(odom.x_m == 12.5f);
  CHECK(odom.theta_rad == 2.5f);
  lcm.publish("ROBOT7/ODOM", &odom);
  pump(lcm);

  REQUIRE(port.twists.size() == 1u);
  CHECK(port.twists[0].stamp_ns == 900);
  CHECK(port.twists[0].v1_mps == 1.5f);
  CHECK(port.twists[0].v2_mps == -0.25f);
  CHECK(port.twists[0].w_rps == 0.125f);
  REQUIRE(port.odometry.size() == 1u);
  CHECK(port.odometry[0].stamp_ns == 950);
  CHECK(port.odometry[0].pose.x == 12.5f);
  CHECK(port.odometry[0].pose.y == -3.25f);
  CHECK(port.odometry[0].pose.theta == 2.5f);
  CHECK(port.odometry[0].wrap_m == 0.0f);
  CHECK(in.accepted() == 2u);
  CHECK(in.rejects().total() == 0u);
}

TEST_CASE("twist_t and odometry_t decode only through the guard: garbage, truncation, another type are malformed",
          "[lcm]") {
  const std::vector<std::uint8_t> twist = bytes_of(hal::lcm::to_lcm(hal::TwistSample{1, 0.5f, 0.0f, 0.1f}));
  hal::OdometrySample o;
  o.pose = {1.0f, 2.0f, 0.5f};
  const std::vector<std::uint8_t> odom = bytes_of(hal::lcm::to_lcm(o));
  est_lcm::twist_t t;
  est_lcm::odometry_t m;
  CHECK(hal::lcm::decode_guarded(twist.data(), twist.size(), t, 0) == LcmReject::none);
  CHECK(t.v1_mps == 0.5f);
  CHECK(hal::lcm::decode_guarded(odom.data(), odom.size(), m, 0) == LcmReject::none);
  CHECK(m.y_m == 2.0f);
  CHECK(hal::lcm::decode_guarded(twist.data(), twist.size() - 1, t, 0) == LcmReject::malformed);
  CHECK(hal::lcm::decode_guarded(odom.data(), odom.size(), t, 0) == LcmReject::malformed);  // fingerprint
  std::vector<std::uint8_t> longer = twist;
  longer.push_back(0);
  CHECK(hal::lcm::decode_guarded(longer.data(), longer.size(), t, 0) == LcmReject::malformed);
  CHECK(hal::lcm::decode_guarded(nullptr, 10, t, 0) == LcmReject::malformed);

  lcm::LCM lcm("memq://");
  Recorder port;
  hal::lcm::LcmInputs in(lcm, custom_channels(), port);
  lcm.publish("ROBOT7/CMD_VEL", twist.data(), static_cast<unsigned>(twist.size() - 2));
  lcm.publish("ROBOT7/ODOM", twist.data(), static_cast<unsigned>(twist.size()));
  const std::uint8_t garbage[3] = {7, 7, 7};
  lcm.publish("ROBOT7/ODOM", garbage, sizeof garbage);
  pump(lcm);
  CHECK(in.rejects()[LcmReject::malformed] == 3u);
  CHECK(port.twists.empty());
  CHECK(port.odometry.empty());
}

TEST_CASE("through the HAL gate: a NaN twist, a too fast one and an odometry jump are counted by the validators",
          "[lcm]") {
  struct Clock final : hal::Clock {
    hal::TimeNs now = 0;
    hal::TimeNs now_ns() override { return now; }
  } clock;
  CheckedCounter sink;
  hal::ValidatedInputs gate(hal::InputLimits{}, clock, sink);
  lcm::LCM lcm("memq://");
  hal::lcm::LcmInputs in(lcm, custom_channels(), gate);
  clock.now = 1000 * hal::kNsPerMs;
  est_lcm::twist_t t = hal::lcm::to_lcm(hal::TwistSample{1000 * hal::kNsPerMs, kNaN, 0.0f, 0.0f});
  lcm.publish("ROBOT7/CMD_VEL", &t);
  t.v1_mps = 50.0f;
  lcm.publish("ROBOT7/CMD_VEL", &t);
  t.v1_mps = 1.0f;
  lcm.publish("ROBOT7/CMD_VEL", &t);
  hal::OdometrySample o;
  o.stamp_ns = 1000 * hal::kNsPerMs;
  est_lcm::odometry_t m = hal::lcm::to_lcm(o);
  lcm.publish("ROBOT7/ODOM", &m);
  m.stamp_ns += 4 * hal::kNsPerMs;  // within the 5 ms the clock may lag
  m.x_m = 3.0f;                     // 750 m/s: an odometry reset
  lcm.publish("ROBOT7/ODOM", &m);
  pump(lcm);
  CHECK(in.rejects().total() == 0u);  // well-formed LCM: the HAL judges the values
  CHECK(gate.twist().faults()[hal::Fault::not_finite] == 1u);
  CHECK(gate.twist().faults()[hal::Fault::out_of_range] == 1u);
  CHECK(gate.odometry().faults()[hal::Fault::out_of_range] == 1u);
  CHECK(sink.n == 2);  // the good twist and the first odometry pose
}

TEST_CASE("team messages published by LcmOutputs reach the TeamPort through the validator: echo and duplicates "
          "refused, out of order passed on", "[lcm][team]") {
  lcm::LCM lcm("memq://");
  hal::lcm::Channels ch;
  ch.team = "TEAM";
  hal::lcm::LcmOutputs out(lcm, ch);
  Recorder port;
  hal::lcm::LcmInputs in(lcm, custom_channels(), port);
  hal::team::TeamValidator validator(3, 0);  // this is robot 0 of three
  in.subscribe_team(port, validator);
  in.subscribe_team(port, validator);  // again: still one subscription

  est::team::TeamMessage m;
  m.robot = 1;
  m.control.kind = est::team::ControlKind::omni;
  m.control.dt_s = 0.1f;
  m.control.v1 = 0.25f;
  m.control.v2 = -0.125f;
  m.control.w = 0.5f;
  m.count = 1;
  m.measurements[0] = {est::team::TargetKind::robot, true, 3.0f, -0.75f, est::team::kAnonymous};
  for (std::uint32_t seq : {1u, 3u, 2u, 3u}) {  // 2 late but new, then 3 again
    m.seq = seq;
    m.stamp_ns = static_cast<hal::TimeNs>(seq) * 100 * hal::kNsPerMs;
    out.publish_team(m);
  }
  m.robot = 0;  // this robot's own message, back from the network
  m.seq = 4;
  out.publish_team(m);
  pump(lcm);

  REQUIRE(port.team.size() == 3);
  CHECK(port.team[0].seq == 1u);
  CHECK(port.team[1].seq == 3u);
  CHECK(port.team[2].seq == 2u);
  CHECK(port.team[2].stamp_ns == 200 * hal::kNsPerMs);
  CHECK(port.team[2].control.kind == est::team::ControlKind::omni);
  CHECK(port.team[2].control.v2 == -0.125f);
  CHECK(port.team[2].measurements[0].id == est::team::kAnonymous);
  CHECK(port.team[2].measurements[0].bearing_rad == -0.75f);
  CHECK(validator.counts()[est::team::TeamReject::none] == 2u);
  CHECK(validator.counts()[est::team::TeamReject::out_of_order] == 1u);
  CHECK(validator.counts()[est::team::TeamReject::duplicate] == 1u);
  CHECK(validator.counts()[est::team::TeamReject::unknown_robot] == 1u);
  CHECK(validator.counts(0)[est::team::TeamReject::unknown_robot] == 1u);
  CHECK(validator.counts(1)[est::team::TeamReject::duplicate] == 1u);
  CHECK(in.team_rejects().total() == 0u);
  CHECK(out.publish_failures() == 0u);
}
