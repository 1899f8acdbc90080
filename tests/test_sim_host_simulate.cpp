// sim_host simulate and record: a scenario's sensor stream through the HAL gate and the firmware's filter loop.
// Files well-formed, accuracy once localized within stated bounds, every injected fault counted once with its
// reason (and nothing else rejected), bit-identical repeats, and an LCM log that replays to the same reject counts.
#include <sys/wait.h>
#include <unistd.h>

#include <catch2/catch.hpp>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <lcm/lcm-cpp.hpp>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "hal/lcm/lcm_backend.hpp"
#include "hal/lcm/lcm_convert.hpp"
#include "hal/validated_inputs.hpp"
#include "sim/record.hpp"
#include "scratch_dir.hpp"
#include "sim/scenario.hpp"
#include "sim/sensor_stream.hpp"
#include "sim/simulate.hpp"

#ifndef SIM_HOST_EXE
#error "SIM_HOST_EXE must name the sim_host executable"
#endif

namespace {

namespace fs = std::filesystem;

// Under the sanitizers (host-debug, ~60x slower here) the runs are shorter and lighter; the bounds stay the same.
#if defined(__SANITIZE_ADDRESS__)
constexpr double kRunSeconds = 8.0;
constexpr std::uint32_t kParticles = 300;
#else
constexpr double kRunSeconds = 14.0;
constexpr std::uint32_t kParticles = 1000;
#endif

struct TempDir : est::test::ScratchDir {
  explicit TempDir(const std::string& tag) : ScratchDir("sim_host_simulate_" + tag) {}
};

using est::test::slurp;

// One of every fault class the robot has: each stream carries several faults, all must be told apart.
sim::FaultCounts one_of_each(sim::RobotKind robot) {
  sim::FaultCounts f;
  for (const sim::FaultClassInfo& c : sim::fault_catalogue())
    if (robot == sim::RobotKind::bicycle || c.key.rfind("steering.", 0) != 0) f[c.key] = 1;
  return f;
}

// A short run that tracks from the true start: fixed particle count, every fault class once, a bus outage.
sim::ScenarioConfig short_scenario(sim::RobotKind robot, std::uint64_t seed) {
  sim::ScenarioConfig c;
  c.robot = robot;
  c.seed = seed;
  c.duration_s = kRunSeconds;
  c.kidnap_at_s = -1.0;
  c.burst_at_s = kRunSeconds / 2.0 - 1.0;
  c.burst_ms = 300.0;
  c.faults = one_of_each(robot);
  return c;
}

sim::FilterOptions tracking_filter() {
  sim::FilterOptions f;
  f.start = sim::StartKind::tracking;
  f.particles = kParticles;
  f.kld = false;
  return f;
}

// Reject counts do not depend on the filter: the lightest one that runs.
sim::FilterOptions counting_filter() {
  sim::FilterOptions f = tracking_filter();
  f.particles = 50;
  f.beam_stride = 36;
  return f;
}

std::vector<std::string> split(const std::string& line, char sep) {
  std::vector<std::string> out;
  std::stringstream ss(line);
  std::string item;
  while (std::getline(ss, item, sep)) out.push_back(item);
  return out;
}

}  // namespace

TEST_CASE("simulate writes a trajectory CSV, a faults list and a metrics JSON that parse", "[simulate]") {
  const sim::ScenarioConfig sc = short_scenario(sim::RobotKind::bicycle, 5);
  const sim::FilterOptions fo = tracking_filter();
  const sim::SimWorld world = sim::load_world(sc);
  const sim::SimResult r = sim::run_simulation(sc, fo, world);
  TempDir dir("files");
  sim::write_simulation_outputs(r, sc, fo, world, dir.path.string(), false);

  std::ifstream csv(dir.path / "trajectory.csv");
  std::string line;
  REQUIRE(std::getline(csv, line));
  const std::vector<std::string> header = split(line, ',');
  REQUIRE(header.size() == 15u);
  CHECK(header[0] == "t_s");
  CHECK(header[7] == "position_error_m");
  std::size_t rows = 0;
  double last_t = -1.0;
  bool finite = true, ordered = true, consistent = true;
  while (std::getline(csv, line)) {
    const std::vector<std::string> f = split(line, ',');
    REQUIRE(f.size() == 15u);
    std::vector<double> v;
    for (const std::string& s : f) v.push_back(std::stod(s));
    for (double x : v) finite = finite && std::isfinite(x);
    ordered = ordered && v[0] >= last_t;
    last_t = v[0];
    // The error column is the distance between the truth and estimate columns (5 decimals each).
    consistent = consistent && std::fabs(std::hypot(v[4] - v[1], v[5] - v[2]) - v[7]) < 2e-5;
    ++rows;
  }
  CHECK(finite);
  CHECK(ordered);
  CHECK(consistent);
  CHECK(rows == r.rows.size());
  // 100 Hz predictions over the run, plus one output per applied scan.
  const auto steps = static_cast<std::size_t>(kRunSeconds * 100.0);
  CHECK(rows >= steps - 10u);
  CHECK(rows <= steps + steps / 10u);

  const nlohmann::json j = nlohmann::json::parse(slurp(dir.path / "metrics.json"));
  CHECK(j.at("scenario").at("robot") == "bicycle");
  CHECK(j.at("accuracy").at("rmse_position_m").get<double>() > 0.0);
  CHECK(j.at("faults").at("every_injected_fault_counted_with_its_reason").get<bool>());
  CHECK(j.at("loop").at("outputs").get<std::size_t>() == rows);

  std::ifstream faults(dir.path / "faults.csv");
  REQUIRE(std::getline(faults, line));
  CHECK(line == "t_s,fault,expected_counter,amount");
  std::size_t n = 0;
  while (std::getline(faults, line)) ++n;
  CHECK(n == r.stream.faults.size());
}

TEST_CASE("every injected fault is counted once, with its reason, and a clean stream has no rejects", "[simulate]") {
  for (const sim::RobotKind robot : {sim::RobotKind::bicycle, sim::RobotKind::diff_drive}) {
    const sim::ScenarioConfig sc = short_scenario(robot, 7);
    const sim::SimWorld world = sim::load_world(sc);
    const sim::SimResult r = sim::run_simulation(sc, counting_filter(), world);
    const auto expected = r.stream.expected_counts();
    const auto observed = r.observed_counts();
    INFO("robot " << sim::to_string(robot));
    // The plan reaches every reason the HAL and the loop have for these classes.
    for (const char* k : {"hal.wheel_ticks.duplicate", "hal.wheel_ticks.stale", "hal.wheel_ticks.time_backwards",
                          "hal.wheel_ticks.from_future", "hal.wheel_ticks.out_of_range", "hal.scan.duplicate",
                          "hal.scan.stale", "hal.scan.time_backwards", "hal.scan.from_future",
                          "hal.scan.too_few_valid_beams", "hal.scan.beams_nan", "loop.too_old",
                          "hal.landmarks.duplicate", "hal.landmarks.stale", "hal.landmarks.from_future",
                          "hal.landmarks.not_finite", "hal.landmarks.out_of_range"})
      CHECK(expected.count(k) == 1u);
    if (robot == sim::RobotKind::bicycle) {
      CHECK(expected.at("hal.steering.not_finite") == 1);
      CHECK(expected.at("hal.steering.out_of_range") == 1);
      CHECK(expected.at("hal.steering.time_backwards") == 2);  // late (overtaken by newer samples) and backwards
    }
    CHECK(expected.at("hal.wheel_ticks.time_backwards") == 2);
    CHECK(observed == expected);
    CHECK(r.loop.queue_full == 0u);
    CHECK(r.nonfinite_estimates == 0u);

    sim::ScenarioConfig clean = sc;
    clean.faults.clear();
    const sim::SimResult c = sim::run_simulation(clean, counting_filter(), world);
    CHECK(c.stream.expected_counts().empty());
    CHECK(c.observed_counts().empty());
  }
}

TEST_CASE("tracking through the faults stays within the stated accuracy", "[simulate]") {
  // Stated bounds once localized: position RMSE 10 cm, heading RMSE 2 deg (5 cm grid, 2 cm range noise, a 1 %
  // odometry scale error, wheel slip, a 0.3 s bus outage at 6 s); measured 3.0-3.6 cm and 0.3-0.4 deg, never
  // outside 0.5 m / 10 deg. (An outage at 11 s, where the route turns, loses the differential drive for 2 s: see
  // the report of sim_host simulate --robot diff-drive --seed 11 --burst-at 11.)
  for (const sim::RobotKind robot : {sim::RobotKind::bicycle, sim::RobotKind::diff_drive}) {
    const sim::ScenarioConfig sc = short_scenario(robot, 11);
    const sim::SimResult r = sim::run_simulation(sc, tracking_filter(), sim::load_world(sc));
    const sim::SimMetrics& m = r.metrics;
    std::printf("simulate %s, tracking, %.0f s, every fault class: position RMSE %.3f m (max %.3f), heading RMSE %.2f deg\n",
                sim::to_string(robot), kRunSeconds, m.rmse_position_m, m.max_position_error_m, m.rmse_heading_deg);
    REQUIRE(m.phases.size() == 1u);
    CHECK(m.phases[0].localized);
    CHECK(m.phases[0].time_to_localize_s == 0.0);
    CHECK(m.rmse_position_m < 0.10);
    CHECK(m.rmse_heading_deg < 2.0);
    CHECK(m.outside_bounds_s == 0.0);
  }
}

// Up to 20000 particles (KLD) for 12 s: ~5 s in Release, too slow under the sanitizers (the host-debug preset),
// where the tracking cases above cover the same code paths.
#if defined(__SANITIZE_ADDRESS__)
#define SIM_GLOBAL_TAGS "[simulate][.]"
#else
#define SIM_GLOBAL_TAGS "[simulate]"
#endif

TEST_CASE("global localization converges and a kidnapping is recovered", SIM_GLOBAL_TAGS) {
  // Stated: localized (0.5 m, 10 deg, held 2 s) within 5 s of a uniform start and within 5 s of the kidnapping;
  // measured 1.6 s and 0.8 s for this seed (1.5-3.7 s and 0.3-2.5 s over seeds 1-3 at 4000-6000 particles).
  // Then position RMSE below 15 cm.
  sim::ScenarioConfig sc;
  sc.duration_s = 12.0;
  sc.kidnap_at_s = 6.0;
  sc.burst_at_s = -1.0;
  sc.faults = {};
  sim::FilterOptions fo;
  fo.particles = 6000;
  const sim::SimResult r = sim::run_simulation(sc, fo, sim::load_world(sc));
  const sim::SimMetrics& m = r.metrics;
  REQUIRE(m.phases.size() == 2u);
  std::printf("simulate bicycle, global start, kidnapped at 6 s: converged %.2f s, recovered %.2f s, RMSE %.3f m\n",
              m.phases[0].time_to_localize_s, m.phases[1].time_to_localize_s, m.rmse_position_m);
  CHECK(m.phases[0].localized);
  CHECK(m.phases[0].time_to_localize_s < 5.0);
  CHECK(m.phases[1].localized);
  CHECK(m.phases[1].time_to_localize_s < 5.0);
  CHECK(m.rmse_position_m < 0.15);
  // The truth really moved: the estimate was far off right after the kidnapping.
  bool far = false;
  for (const sim::OutputRow& row : r.rows)
    if (row.t_ns == r.stream.kidnap_ns) far = far || row.position_error_m > 2.0f;
  CHECK(far);
}

TEST_CASE("the same seed gives the same CSV bytes, another seed does not", "[simulate]") {
  TempDir dir("repeat");
  std::string csv[3];
  const std::uint64_t seeds[3] = {3, 3, 4};
  for (int i = 0; i < 3; ++i) {
    sim::ScenarioConfig sc = short_scenario(sim::RobotKind::bicycle, seeds[i]);
    sc.duration_s = kRunSeconds / 2.0;
    sc.burst_at_s = -1.0;
    sim::FaultCounts few;
    for (const char* k : {"scan.late", "scan.dropped", "wheel_ticks.duplicate", "steering.nan"}) few[k] = 1;
    sc.faults = few;
    const sim::FilterOptions fo = tracking_filter();
    const sim::SimWorld world = sim::load_world(sc);
    const sim::SimResult r = sim::run_simulation(sc, fo, world);
    const fs::path d = dir.path / std::to_string(i);
    sim::write_simulation_outputs(r, sc, fo, world, d.string(), false);
    csv[i] = slurp(d / "trajectory.csv");
  }
  REQUIRE(csv[0].size() > 10000u);
  CHECK(csv[0] == csv[1]);
  CHECK(csv[0] != csv[2]);
}

TEST_CASE("record writes an LCM log with every message, which replays through the HAL to the expected rejects",
          "[record]") {
  const sim::ScenarioConfig sc = short_scenario(sim::RobotKind::bicycle, 9);
  const sim::SimWorld world = sim::load_world(sc);
  const sim::SensorStream s = sim::generate_stream(sc, world);
  TempDir dir("record");
  const std::string path = (dir.path / "run.lcmlog").string();
  const sim::RecordSummary summary = sim::record_lcm_log(s, path);

  std::map<sim::StreamKind, std::uint64_t> events;
  for (const sim::StreamEvent& e : s.events) ++events[e.kind];
  const hal::lcm::Channels ch;
  CHECK(summary.messages.at(ch.wheel_ticks) == events[sim::StreamKind::wheel_ticks]);
  CHECK(summary.messages.at(ch.steering) == events[sim::StreamKind::steering]);
  CHECK(summary.messages.at(ch.range_scan) == events[sim::StreamKind::scan]);
  CHECK(summary.messages.at(ch.landmarks) == events[sim::StreamKind::landmarks]);
  CHECK(events[sim::StreamKind::landmarks] > 0u);
  CHECK(summary.messages.at(ch.ground_truth) == s.truth.size());
  // Encoders at 100 Hz, steering at 50 Hz, scans at 10 Hz, less the 0.3 s outage, less one drop, plus one
  // duplicate each.
  const auto tenths = static_cast<std::uint64_t>(kRunSeconds * 10.0);
  CHECK(events[sim::StreamKind::wheel_ticks] == 10u * tenths - 30u - 1u + 1u);
  CHECK(events[sim::StreamKind::steering] == 5u * tenths - 15u - 1u + 1u);
  CHECK(events[sim::StreamKind::scan] == tenths - 3u - 1u + 1u);

  // Read it back as a replay would: decode each message, convert, validate with the HAL clock at the event time.
  struct NullPort final : hal::ValidatedSensorPort {
    void on_wheel_motion(const hal::WheelTickDelta&) override {}
    void on_steering(const hal::SteeringSample&) override {}
    void on_range_scan(const hal::RangeScanView&) override {}
    void on_landmarks(const hal::LandmarkSightingView&) override {}
  } sink;
  struct EventClock final : hal::Clock {
    hal::TimeNs now = 0;
    hal::TimeNs now_ns() override { return now; }
  } clock;
  hal::ValidatedInputs inputs(s.limits, clock, sink);
  ::lcm::LogFile log(path, "r");
  REQUIRE(log.good());
  std::map<std::string, std::uint64_t> read;
  std::int64_t last_us = -1;
  bool ordered = true, decoded = true;
  std::size_t scan_beams_ok = 0;
  for (const ::lcm::LogEvent* e = log.readNextEvent(); e != nullptr; e = log.readNextEvent()) {
    ++read[e->channel];
    ordered = ordered && e->timestamp >= last_us;
    last_us = e->timestamp;
    clock.now = e->timestamp * 1000;
    if (e->channel == ch.wheel_ticks) {
      est_lcm::encoder_ticks_t m;
      decoded = decoded && m.decode(e->data, 0, e->datalen) == e->datalen;
      hal::WheelTicks t;
      decoded = decoded && hal::lcm::to_hal(m, sim::kEncoderCounterBits, t) == hal::lcm::LcmReject::none;
      inputs.on_wheel_ticks(t);
    } else if (e->channel == ch.steering) {
      est_lcm::steering_t m;
      decoded = decoded && m.decode(e->data, 0, e->datalen) == e->datalen;
      inputs.on_steering(hal::lcm::to_hal(m));
    } else if (e->channel == ch.range_scan) {
      est_lcm::range_scan_t m;
      decoded = decoded && m.decode(e->data, 0, e->datalen) == e->datalen;
      hal::RangeScanView v;
      decoded = decoded && hal::lcm::to_hal(m, v) == hal::lcm::LcmReject::none;
      if (v.count == static_cast<std::size_t>(sc.beams)) ++scan_beams_ok;
      inputs.on_range_scan(v);
    } else if (e->channel == ch.landmarks) {
      est_lcm::landmark_sighting_t m;
      decoded = decoded && m.decode(e->data, 0, e->datalen) == e->datalen;
      hal::LandmarkSighting<hal::kMaxLandmarkFeatures> l;
      decoded = decoded && hal::lcm::to_hal(m, l) == hal::lcm::LcmReject::none;
      inputs.on_landmarks(l.view());
    } else if (e->channel == ch.ground_truth) {
      est_lcm::ground_truth_t m;
      decoded = decoded && m.decode(e->data, 0, e->datalen) == e->datalen;
    }
  }
  CHECK(ordered);
  CHECK(decoded);
  CHECK(read == summary.messages);
  CHECK(scan_beams_ok == events[sim::StreamKind::scan]);
  // Every HAL reject of the replay is one the scenario injected (loop.too_old needs the loop, not replayed here).
  std::map<std::string, int> replayed;
  const std::pair<const char*, const hal::FaultCounters*> kinds[] = {{"wheel_ticks", &inputs.wheels().faults()},
                                                                      {"steering", &inputs.steering().faults()},
                                                                      {"scan", &inputs.scan().faults()},
                                                                      {"landmarks", &inputs.landmarks().faults()}};
  for (const auto& [name, c] : kinds)
    for (std::size_t i = 1; i < hal::kFaultCount; ++i)
      if (c->count[i] > 0)
        replayed[std::string("hal.") + name + "." + hal::to_string(static_cast<hal::Fault>(i))] =
            static_cast<int>(c->count[i]);
  if (inputs.scan().beams().not_a_number > 0)
    replayed["hal.scan.beams_nan"] = static_cast<int>(inputs.scan().beams().not_a_number);
  std::map<std::string, int> expected = s.expected_counts();
  expected.erase("loop.too_old");
  CHECK(replayed == expected);

  const nlohmann::json side = nlohmann::json::parse(sim::record_sidecar_json(s, sc, world, summary, path));
  CHECK(side.at("messages").at(ch.range_scan).get<std::uint64_t>() == events[sim::StreamKind::scan]);
  // The late scan, and the late sighting once per feature (the loop takes one input per feature).
  CHECK(side.at("expected_reject_counts").at("loop.too_old").get<int>() == s.expected_counts().at("loop.too_old"));
  CHECK(side.at("expected_reject_counts").at("loop.too_old").get<int>() >= 2);
}

TEST_CASE("sim_host simulate runs from the command line, draws its figures and rejects bad options", "[simulate]") {
  TempDir dir("cli");
  const auto run = [](const std::string& args) {
    const std::string cmd = std::string("'") + SIM_HOST_EXE + "' " + args + " > /dev/null 2>&1";
    const int rc = std::system(cmd.c_str());
    return WIFEXITED(rc) ? WEXITSTATUS(rc) : -1;
  };
  const fs::path out = dir.path / "run";
  REQUIRE(run("simulate --out '" + out.string() +
              "' --duration 5 --start tracking --particles 500 --no-kld --kidnap-at -1 --burst-at -1 --faults none "
              "--fault scan.stale=1") == 0);
  for (const char* f : {"trajectory.csv", "metrics.json", "faults.csv", "trajectory.png", "errors.png", "particles.png"})
    CHECK(fs::exists(out / f));
  for (const char* png : {"trajectory.png", "errors.png", "particles.png"}) {
    const std::string bytes = slurp(out / png);
    REQUIRE(bytes.size() > 8u);
    CHECK(bytes.compare(0, 8, "\x89PNG\r\n\x1a\n") == 0);
  }
  CHECK(run("simulate --out '" + out.string() + "' --fault bogus.class=1") != 0);
  CHECK(run("simulate --out '" + out.string() + "' --robot diff-drive --fault steering.nan=1") != 0);
  CHECK(run("simulate --out '" + out.string() + "' --scan-hz 7") != 0);
  CHECK(run("simulate --out '" + out.string() + "' --map /nonexistent.yaml --route '1,1;2,2'") != 0);
  CHECK(run("record --out '" + (dir.path / "x.lcmlog").string() + "' --duration 3 --faults none") == 0);
  CHECK(fs::file_size(dir.path / "x.lcmlog") > 50000u);  // 3 s: 30 scans of 360 floats alone are 43 kB
}
