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

#include <CLI/CLI.hpp>
#include <cstring>
#include <est_lcm/pose_estimate_t.hpp>

#include "hal/lcm/lcm_backend.hpp"
#include "node/node.hpp"
#include "node/node_config.hpp"
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

// The robots the per-model loops run. Under the sanitizers four that between them use every motion input (traction
// ticks and steering, four wheels, twist, odometry); the Release preset runs all six.
#if defined(__SANITIZE_ADDRESS__)
const std::vector<sim::RobotKind> kModelsUnderTest = {sim::RobotKind::bicycle, sim::RobotKind::omni,
                                                      sim::RobotKind::velocity, sim::RobotKind::odometry};
#else
const std::vector<sim::RobotKind> kModelsUnderTest(std::begin(sim::kRobots), std::end(sim::kRobots));
#endif

struct TempDir : est::test::ScratchDir {
  explicit TempDir(const std::string& tag) : ScratchDir("sim_host_simulate_" + tag) {}
};

using est::test::slurp;

std::string ch_pose() { return hal::lcm::Channels{}.pose; }

// Checked samples go nowhere (a replay of the HAL gate alone).
struct NullPort final : hal::PortImplementation<NullPort, hal::ValidatedSensorPort> {
  template <typename Checked>
  void handle(const Checked&) {}
};

// One of every fault class the robot has: each stream carries several faults, all must be told apart.
sim::FaultCounts one_of_each(sim::RobotKind robot) {
  sim::FaultCounts f;
  for (const sim::FaultClassInfo& c : sim::fault_catalogue())
    if (sim::fault_applies(robot, c.key)) f[c.key] = 1;
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
  for (const sim::RobotKind robot : sim::kRobots) {
    const sim::ScenarioConfig sc = short_scenario(robot, 7);
    const sim::SimWorld world = sim::load_world(sc);
    const sim::SimResult r = sim::run_simulation(sc, counting_filter(), world);
    const auto expected = r.stream.expected_counts();
    const auto observed = r.observed_counts();
    INFO("robot " << sim::to_string(robot));
    // The plan reaches every reason the HAL and the loop have for these classes.
    for (const char* k : {"hal.scan.duplicate", "hal.scan.stale", "hal.scan.time_backwards", "hal.scan.from_future",
                          "hal.scan.too_few_valid_beams", "hal.scan.beams_nan", "loop.too_old",
                          "hal.landmarks.duplicate", "hal.landmarks.stale", "hal.landmarks.from_future",
                          "hal.landmarks.not_finite", "hal.landmarks.out_of_range"})
      CHECK(expected.count(k) == 1u);
    // And those of the robot's motion stream: encoders, twist or odometry.
    const char* motion = sim::has_wheel_ticks(robot) ? "wheel_ticks" : sim::has_twist(robot) ? "twist" : "odometry";
    for (const char* reason : {"duplicate", "stale", "from_future", "out_of_range"})
      CHECK(expected.count(std::string("hal.") + motion + "." + reason) == 1u);
    CHECK(expected.at(std::string("hal.") + motion + ".time_backwards") == 2);  // late (overtaken) and backwards
    if (!sim::has_wheel_ticks(robot)) CHECK(expected.count(std::string("hal.") + motion + ".not_finite") == 1u);
    if (robot == sim::RobotKind::bicycle) {
      CHECK(expected.at("hal.steering.not_finite") == 1);
      CHECK(expected.at("hal.steering.out_of_range") == 1);
      CHECK(expected.at("hal.steering.time_backwards") == 2);
    }
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

TEST_CASE("every motion model tracks through the faults within the stated accuracy", "[simulate]") {
  // Stated bounds once localized: position RMSE 10 cm, heading RMSE 2 deg (5 cm grid, 2 cm range noise, a 1 %
  // odometry scale error, wheel slip, a 0.3 s bus outage at 6 s, one fault of each class of the robot's streams);
  // measured 1.5-3.6 cm and 0.2-0.6 deg over the six robots, never outside 0.5 m / 10 deg. (An outage at 11 s,
  // where the route turns, loses the differential drive for 2 s: see the report of sim_host simulate --robot
  // diff-drive --seed 11 --burst-at 11.)
  for (const sim::RobotKind robot : kModelsUnderTest) {
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

// The default scenario (60 s, up to 20000 particles with KLD), the six models as processes, the steered model's 20
// runs: ~2-10 s each in Release, too slow under the sanitizers (the host-debug preset), where the tracking cases
// cover the same code paths.
#if defined(__SANITIZE_ADDRESS__)
#define SIM_GLOBAL_TAGS "[simulate][.]"
#else
#define SIM_GLOBAL_TAGS "[simulate]"
#endif

TEST_CASE("the default scenario localizes, loses and regains the estimate at the kidnapping, and injects nothing "
          "while localized",
          SIM_GLOBAL_TAGS) {
  // Stated: localized (0.5 m, 10 deg, held 2 s) within 5 s of the uniform start and within 5 s of the loss the
  // kidnapping causes; while localized under 1 % of the particles drawn are injected and the count averages at
  // most twice the KLD floor; position RMSE below 10 cm. Measured for this seed: 1.5 s, 0.8 s, 0 injected, 500 on
  // average, 2.9 cm (seeds 1-20 of both robots: at most 3.9 s and 2.0 s, none injected while localized).
  // What `sim_host simulate --out DIR` runs: the office, the bicycle, 60 s, seed 1, the default fault plan, a bus
  // outage at 45 s and the kidnapping at 30 s; a global start, up to 20000 particles, KLD from 500.
  sim::ScenarioConfig sc;
  sc.faults = sim::default_fault_counts(sc.robot);
  const sim::FilterOptions fo;
  const sim::SimWorld world = sim::load_world(sc);
  const sim::SimResult r = sim::run_simulation(sc, fo, world);
  const sim::SimMetrics& m = r.metrics;
  REQUIRE(m.phases.size() == 2u);
  const sim::PhaseMetrics& g = m.phases[0];
  const sim::PhaseMetrics& k = m.phases[1];
  std::printf("simulate default (seed 1): converged %.2f s (injected %.4f, particles mean %.0f max %u); kidnapping "
              "carried %.1f m, lost at %.2f s, recovered %.2f s later (injected %.4f, particles mean %.0f max %u); "
              "RMSE %.3f m\n",
              g.time_to_localize_s, g.injected_share, g.particles_mean, g.particles_max, r.stream.kidnap_distance_m,
              k.lost_at_s, k.time_to_localize_s, k.injected_share, k.particles_mean, k.particles_max,
              m.rmse_position_m);
  CHECK(g.localized);
  CHECK(g.time_to_localize_s < 5.0);
  // The kidnapping really moved the robot: the estimate left the bounds at once, and came back.
  CHECK(r.stream.kidnap_distance_m >= sim::kKidnapMinDistanceM);
  CHECK(k.lost_at_s >= k.start_s);
  CHECK(k.lost_at_s < k.start_s + 0.2);
  CHECK(k.localized);
  CHECK(k.time_to_localize_s < 5.0);
  CHECK(k.localized_at_s == Approx(k.lost_at_s + k.time_to_localize_s).margin(1e-6));
  for (const sim::PhaseMetrics* p : {&g, &k}) {
    INFO(p->name);
    CHECK(p->drawn_particles > 0u);
    CHECK(p->injected_share >= 0.0);
    CHECK(p->injected_share < 0.01);
    CHECK(p->particles_mean <= 2.0 * fo.kld_min);
    CHECK(p->particles_max >= fo.kld_min);
  }
  CHECK(m.rmse_position_m < 0.10);

  // The same figures in metrics.json.
  TempDir dir("default");
  sim::write_simulation_outputs(r, sc, fo, world, dir.path.string(), false);
  const nlohmann::json j = nlohmann::json::parse(slurp(dir.path / "metrics.json"));
  REQUIRE(j.at("phases").size() == 2u);
  for (const auto& p : j.at("phases")) {
    for (const char* key : {"injected_share", "particles_mean", "particles_max", "lost_at_s", "localized_at_s",
                            "time_to_localize_s", "injected_particles", "drawn_particles"})
      CHECK(p.contains(key));
    CHECK(p.at("injected_share").get<double>() < 0.01);
    CHECK(p.at("particles_mean").get<double>() <= 2.0 * fo.kld_min);
  }
  CHECK(j.at("phases")[1].at("lost_at_s").get<double>() == Approx(k.lost_at_s));
  CHECK(j.at("time_to_recover_s").get<double>() == Approx(k.time_to_localize_s));
  CHECK(j.at("scenario").at("kidnap_distance_m").get<double>() >= sim::kKidnapMinDistanceM);
  CHECK(j.at("mcl").at("drawn_particles").get<std::uint64_t>() >=
        j.at("mcl").at("injected_particles").get<std::uint64_t>());
}

TEST_CASE("a tracking start is never lost and injects nothing while localized", "[simulate]") {
  sim::ScenarioConfig sc = short_scenario(sim::RobotKind::bicycle, 5);
  sc.faults = {};
  sc.burst_at_s = -1.0;
  const sim::SimResult r = sim::run_simulation(sc, tracking_filter(), sim::load_world(sc));
  REQUIRE(r.metrics.phases.size() == 1u);
  CHECK(r.metrics.phases[0].lost_at_s == -1.0);  // tracking: never lost
  CHECK(r.metrics.phases[0].localized);
  CHECK(r.metrics.phases[0].injected_share == 0.0);
}

TEST_CASE("the particle panels are at distinct times: times that meet share one panel", "[simulate]") {
  // A 2 s run: its half-way is its 1 s snapshot; 3 s and 10 s are past its end. The initial belief is the panel
  // before the first scan, at its time.
  sim::ScenarioConfig sc = short_scenario(sim::RobotKind::bicycle, 5);
  sc.duration_s = 2.0;
  sc.faults = {};
  sc.burst_at_s = -1.0;
  sim::FilterOptions f = tracking_filter();
  f.particles = 200;
  const sim::SimResult r = sim::run_simulation(sc, f, sim::load_world(sc));
  std::vector<std::string> labels;
  for (std::size_t i = 0; i < r.snapshots.size(); ++i) {
    labels.push_back(r.snapshots[i].label);
    if (i > 1) CHECK(r.snapshots[i].t_ns > r.snapshots[i - 1].t_ns);
  }
  CHECK(labels == std::vector<std::string>{"initial belief", "first scan", "1 s, half-way", "end"});
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
  NullPort sink;
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
      inputs.on(t);
    } else if (e->channel == ch.steering) {
      est_lcm::steering_t m;
      decoded = decoded && m.decode(e->data, 0, e->datalen) == e->datalen;
      inputs.on(hal::lcm::to_hal(m));
    } else if (e->channel == ch.range_scan) {
      est_lcm::range_scan_t m;
      decoded = decoded && m.decode(e->data, 0, e->datalen) == e->datalen;
      hal::RangeScanView v;
      decoded = decoded && hal::lcm::to_hal(m, v) == hal::lcm::LcmReject::none;
      if (v.count == static_cast<std::size_t>(sc.beams)) ++scan_beams_ok;
      inputs.on(v);
    } else if (e->channel == ch.landmarks) {
      est_lcm::landmark_sighting_t m;
      decoded = decoded && m.decode(e->data, 0, e->datalen) == e->datalen;
      hal::LandmarkSighting<hal::kMaxLandmarkFeatures> l;
      decoded = decoded && hal::lcm::to_hal(m, l) == hal::lcm::LcmReject::none;
      inputs.on(l.view());
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
  // The errors' legend names what the run has: a tracking run at a fixed particle count, no kidnapping, no outage.
  const std::string errors_gp = slurp(out / "errors.gp");
  CHECK(errors_gp.find("title 'localized from'") != std::string::npos);
  CHECK(errors_gp.find("title 'particles (fixed)'") != std::string::npos);
  for (const char* absent : {"title 'kidnapping'", "title 'lost at (kidnapping)'", "title 'bus outage'"})
    CHECK(errors_gp.find(absent) == std::string::npos);
  CHECK(run("simulate --out '" + out.string() + "' --fault bogus.class=1") != 0);
  CHECK(run("simulate --out '" + out.string() + "' --robot diff-drive --fault steering.nan=1") != 0);
  CHECK(run("simulate --out '" + out.string() + "' --scan-hz 7") != 0);
  CHECK(run("simulate --out '" + out.string() + "' --map /nonexistent.yaml --route '1,1;2,2'") != 0);
  CHECK(run("record --out '" + (dir.path / "x.lcmlog").string() + "' --duration 3 --faults none") == 0);
  CHECK(fs::file_size(dir.path / "x.lcmlog") > 50000u);  // 3 s: 30 scans of 360 floats alone are 43 kB
}

TEST_CASE("sim_host simulate --robot runs each of the six motion models and reports its accuracy", SIM_GLOBAL_TAGS) {
  // The executable as a user runs it; a clean 6 s run from the true start for each model: localized throughout,
  // position RMSE under 10 cm (measured 1-3 cm), and the accuracy fields that metrics.json keeps.
  TempDir dir("robots");
  for (const char* robot : {"velocity", "odometry", "bicycle", "diff-drive", "omni", "holonomic"}) {
    INFO("--robot " << robot);
    const fs::path out = dir.path / robot;
    const std::string cmd = std::string(SIM_HOST_EXE) + " simulate --robot " + robot + " --seed 3 --duration 6 --out " +
                            out.string() + " --start tracking --particles 500 --no-kld --faults none --kidnap-at -1 "
                            "--burst-at -1 --no-plots > " + (out.string() + ".log") + " 2>&1";
    REQUIRE(std::system(cmd.c_str()) == 0);
    const nlohmann::json j = nlohmann::json::parse(slurp(out / "metrics.json"));
    CHECK(j.at("scenario").at("robot") == robot);
    const double rmse = j.at("accuracy").at("rmse_position_m").get<double>();
    const double heading = j.at("accuracy").at("rmse_heading_deg").get<double>();
    std::printf("sim_host simulate --robot %s: position RMSE %.3f m, heading RMSE %.2f deg\n", robot, rmse, heading);
    CHECK(rmse > 0.0);
    CHECK(rmse < 0.10);
    CHECK(heading < 2.0);
    CHECK(j.at("phases").at(0).at("localized").get<bool>());
  }
}

TEST_CASE("the steered range model tracks a handlebar rangefinder where the steering reading taken as exact does not",
          SIM_GLOBAL_TAGS) {
  // The exercise's robot: a bicycle whose 360-beam rangefinder sits on its handlebar (0.15 m ahead of the steering
  // axis), the handlebar in one of six positions from stop to stop (+-60 deg). Measured over seeds 1-5, 20 s from the
  // true start: the marginalized model (M = 6, steering estimated from the scans) tracks with position RMSE 3.5-6 cm
  // and heading RMSE 0.7-0.8 deg both with a steering sensor biased by 10 deg and without one (one of the five
  // seeds without a sensor settles one handle position off: heading RMSE 20 deg, position 6 cm); the reading taken as
  // exact is never localized (no sensor) or holds the heading 8-10 deg off (biased). Stated: the marginalized model
  // within 10 cm and 2 deg RMSE in at least 4 of 5 seeds of each case; the exact reading in none.
  struct Case {
    const char* what;
    bool sensor;
    double bias_deg;
  };
  for (const Case c : {Case{"a steering sensor biased by 10 deg", true, 10.0}, Case{"no steering sensor", false, 0.0}}) {
    int marginalized_tracks = 0, exact_tracks = 0;
    for (std::uint64_t seed = 1; seed <= 5; ++seed) {
      sim::ScenarioConfig sc;
      sc.robot = sim::RobotKind::bicycle;
      sc.seed = seed;
      sc.duration_s = 20.0;
      sc.kidnap_at_s = -1.0;
      sc.burst_at_s = -1.0;
      sc.faults = {};
      sc.handlebar = true;
      sc.handle_detents = 6;
      sc.steering_sensor = c.sensor;
      sc.steering_bias_deg = c.bias_deg;
      const sim::SimWorld world = sim::load_world(sc);
      for (const std::int32_t positions : {6, 0}) {
        sim::FilterOptions fo = tracking_filter();
        fo.range_model = node::RangeModel::steered;
        fo.handle_positions = positions;
        fo.handle_reading_sigma_rad = 0.2f;  // the filter is told not to trust the reading to better than 11 deg
        const sim::SimResult r = sim::run_simulation(sc, fo, world);
        const sim::SimMetrics& m = r.metrics;
        const bool tracks = m.phases.at(0).localized && m.rmse_position_m < 0.10 && m.rmse_heading_deg < 2.0;
        std::printf("steered, %s, seed %d, %s: localized %d, position RMSE %.3f m, heading RMSE %.2f deg\n", c.what,
                    static_cast<int>(seed), positions == 0 ? "reading taken as exact" : "marginalized over 6",
                    m.phases.at(0).localized ? 1 : 0, m.rmse_position_m, m.rmse_heading_deg);
        (positions == 0 ? exact_tracks : marginalized_tracks) += tracks ? 1 : 0;
      }
    }
    INFO(c.what);
    CHECK(marginalized_tracks >= 4);
    CHECK(exact_tracks == 0);
  }
}

TEST_CASE("record writes each robot's motion stream on its channel: encoder ticks, twist or odometry", "[simulate]") {
  TempDir dir("record_kinds");
  const hal::lcm::Channels ch;
  for (const sim::RobotKind robot : sim::kRobots) {
    INFO("robot " << sim::to_string(robot));
    sim::ScenarioConfig sc = short_scenario(robot, 4);
    sc.duration_s = 3.0;
    sc.faults = {};
    const sim::SimWorld world = sim::load_world(sc);
    const sim::SensorStream s = sim::generate_stream(sc, world);
    const std::string path = (dir.path / (std::string(sim::to_string(robot)) + ".lcmlog")).string();
    const sim::RecordSummary summary = sim::record_lcm_log(s, path);
    std::map<sim::StreamKind, std::uint64_t> events;
    for (const sim::StreamEvent& e : s.events) ++events[e.kind];
    const auto messages = [&](const std::string& c) { return summary.messages.count(c) ? summary.messages.at(c) : 0u; };
    CHECK(messages(ch.wheel_ticks) == events[sim::StreamKind::wheel_ticks]);
    CHECK(messages(ch.twist) == events[sim::StreamKind::twist]);
    CHECK(messages(ch.odometry) == events[sim::StreamKind::odometry]);
    CHECK((events[sim::StreamKind::wheel_ticks] > 0u) == sim::has_wheel_ticks(robot));
    CHECK((events[sim::StreamKind::twist] > 0u) == sim::has_twist(robot));
    CHECK((events[sim::StreamKind::odometry] > 0u) == sim::has_odometry(robot));
    // The sidecar names the estimator_node options of this robot.
    const nlohmann::json side = nlohmann::json::parse(sim::record_sidecar_json(s, sc, world, summary, path));
    CHECK(side.at("estimator_node_options").get<std::string>().find(std::string("--model ") + sim::to_string(robot)) !=
          std::string::npos);
  }
}

namespace {
struct ReplayCase {
  sim::RobotKind robot;
  node::RangeModel range_model;
  node::BeamCast beam_cast;
};
}  // namespace

TEST_CASE("estimator_node's replay of a recorded run gives the simulator's estimates, bit for bit", "[simulate]") {
  // One composition: sim_host runs the estimator pipeline in process; estimator_node, given the options the
  // record sidecar names, runs the same pipeline on the recorded log. Without faults (a replay takes each message's
  // stamp as the HAL's clock, so staleness is not replayed) the two publish the same estimates, bit for bit.
  // Every model with the likelihood field, and the beam model with each of its casts (its options in the sidecar).
  TempDir dir("replay");
  std::vector<ReplayCase> cases;
  for (const sim::RobotKind robot : kModelsUnderTest)
    cases.push_back({robot, node::RangeModel::likelihood_field, node::BeamCast::table});
  cases.push_back({sim::RobotKind::velocity, node::RangeModel::beam, node::BeamCast::table});
  cases.push_back({sim::RobotKind::velocity, node::RangeModel::beam, node::BeamCast::cone});
  for (const ReplayCase& c : cases) {
    const sim::RobotKind robot = c.robot;
    INFO("robot " << sim::to_string(robot) << ", " << node::to_string(c.range_model) << " range model, "
                  << node::to_string(c.beam_cast) << " cast");
    sim::ScenarioConfig sc = short_scenario(robot, 6);
    sc.duration_s = 4.0;
    sc.faults = {};
    sc.burst_at_s = -1.0;
    sim::FilterOptions fo = tracking_filter();
    fo.particles = 300;
    fo.range_model = c.range_model;
    fo.beam_cast = c.beam_cast;
    const sim::SimWorld world = sim::load_world(sc);
    const sim::SimResult r = sim::run_simulation(sc, fo, world);
    const std::string log = (dir.path / (std::string(sim::to_string(robot)) + "-" + node::to_string(c.range_model) +
                                         "-" + node::to_string(c.beam_cast) + ".lcmlog")).string();
    const sim::RecordSummary summary = sim::record_lcm_log(r.stream, log);
    // The options of this run's estimator (the sidecar's, node::command_line, are those of a default tracking
    // filter).
    std::vector<std::string> args{"estimator_node", "--replay", log, "--wheel-counter-bits", "32"};
    std::istringstream words(node::command_line(sim::estimator_spec(sc, fo, r.stream), "office", "office"));
    for (std::string w; words >> w;) args.push_back(w);
    const std::string out = log + ".out";
    for (const char* a : {"--out", out.c_str(), "--quiet"}) args.emplace_back(a);
    std::vector<char*> argv;
    for (std::string& a : args) argv.push_back(a.data());
    node::NodeConfig config;
    CLI::App app;
    node::add_options(app, config);
    app.parse(static_cast<int>(argv.size()), argv.data());
    node::finish_options(app, config);
    {
      node::Node n(config);  // its log is complete once it is gone
      REQUIRE(n.run() == 0);
    }

    ::lcm::LogFile in(out, "r");
    REQUIRE(in.good());
    std::size_t k = 0, same = 0;
    while (const ::lcm::LogEvent* e = in.readNextEvent()) {
      if (e->channel != ch_pose()) continue;
      est_lcm::pose_estimate_t m;
      REQUIRE(m.decode(e->data, 0, e->datalen) == e->datalen);
      REQUIRE(k < r.rows.size());
      const sim::OutputRow& row = r.rows[k++];
      same += m.stamp_ns == row.t_ns && std::memcmp(&m.x_m, &row.estimate.x, 4) == 0 &&
              std::memcmp(&m.y_m, &row.estimate.y, 4) == 0 && std::memcmp(&m.theta_rad, &row.estimate.theta, 4) == 0;
    }
    CHECK(k == r.rows.size());
    CHECK(same == k);
    CHECK(k > 390u);  // 4 s at 100 Hz
  }
}

// Issue 37: a filter that does not match the robot's sensors is refused with the reason, before anything runs.
TEST_CASE("simulate refuses a range model that does not match where the rangefinder is", "[simulate]") {
  sim::ScenarioConfig sc;
  sc.robot = sim::RobotKind::bicycle;
  sc.duration_s = 1.0;
  sc.faults = {};
  const sim::SimWorld world = sim::load_world(sc);
  sim::FilterOptions fo = tracking_filter();
  const auto reason = [&]() -> std::string {
    try {
      sim::run_simulation(sc, fo, world);
    } catch (const std::invalid_argument& e) {
      return e.what();
    }
    return "";
  };
  // The steered model with the rangefinder fixed on the frame.
  sc.handlebar = false;
  fo.range_model = node::RangeModel::steered;
  CHECK_THAT(reason(), Catch::Contains("fixed on the frame"));
  // The rangefinder on the handlebar with a fixed-frame model, either of them.
  sc.handlebar = true;
  for (const node::RangeModel m : {node::RangeModel::likelihood_field, node::RangeModel::beam}) {
    fo.range_model = m;
    CHECK_THAT(reason(), Catch::Contains("on the handlebar"));
  }
  // Matched: it runs.
  fo.range_model = node::RangeModel::steered;
  CHECK(reason().empty());
}
