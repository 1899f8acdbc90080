// sim_host run and list (sim/scenario_run.hpp, src/run_command.cpp): each built-in scenario run for a short time
// with bounds on what it reaches, a scenario FILE giving simulate's files for the same options byte for byte, and a
// malformed file refused before anything runs.
#include <catch2/catch.hpp>

#include <sys/wait.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <regex>
#include <string>

#include "node_harness.hpp"
#include "scratch_dir.hpp"
#include "sim/builtin_scenarios.hpp"
#include "sim/scenario_run.hpp"
#include "sim/simulate.hpp"

#ifndef SIM_HOST_EXE
#error "SIM_HOST_EXE must name the sim_host executable"
#endif
#ifndef ESTIMATOR_NODE_EXE
#error "ESTIMATOR_NODE_EXE must name the estimator_node executable"
#endif

namespace {

namespace fs = std::filesystem;
using est::test::ScratchDir;
using est::test::slurp;

// Runs sim_host with `args`; returns its exit status and what it wrote on stdout (stderr to `err` when given).
int sim_host(const std::string& args, std::string* out = nullptr, const fs::path& err = {}) {
  const std::string cmd = std::string("'") + SIM_HOST_EXE + "' " + args + " 2>" +
                          (err.empty() ? std::string("/dev/null") : "'" + err.string() + "'");
  FILE* p = popen(cmd.c_str(), "r");
  REQUIRE(p != nullptr);
  std::array<char, 4096> buf{};
  std::string text;
  for (std::size_t n; (n = fread(buf.data(), 1, buf.size(), p)) > 0;) text.append(buf.data(), n);
  const int status = pclose(p);
  if (out != nullptr) *out = text;
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

nlohmann::json read_json(const fs::path& p) { return nlohmann::json::parse(slurp(p)); }

// A built-in single-robot scenario, run in process at its own length (each takes 1-2 s here).
sim::SimResult run_builtin(const std::string& name, double& wall_s) {
  sim::ScenarioFile f = sim::load_scenario(name);
  REQUIRE(f.runner == sim::ScenarioRunner::simulate);
  const double duration_s = f.scenario.duration_s;
  const auto t0 = std::chrono::steady_clock::now();
  const sim::SimWorld world = sim::load_world(f.scenario);
  sim::SimResult r = sim::run_simulation(f.scenario, f.filter, world);
  wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::printf("%s, %.0f s: position RMSE %.3f m, heading RMSE %.2f deg (localized %.1f s), %.1f s wall\n",
              name.c_str(), duration_s, r.metrics.rmse_position_m, r.metrics.rmse_heading_deg,
              r.metrics.localized_time_s, wall_s);
  return r;
}

}  // namespace

TEST_CASE("sim_host list lists every built-in scenario with its runner and description", "[sim_host_run]") {
  std::string out;
  REQUIRE(sim_host("list", &out) == 0);
  for (const sim::BuiltinScenario& b : sim::builtin_scenarios()) {
    INFO(out);
    CHECK(out.find(b.name + " ") != std::string::npos);
    CHECK(out.find(sim::parse_scenario(b.text, b.path).description) != std::string::npos);
  }
  CHECK(std::regex_search(out, std::regex("\ncoop-slam-team +team +cooperative EKF-SLAM")));
  CHECK(std::regex_search(out, std::regex("\nkidnapped +robot +")));
}

TEST_CASE("run FILE writes what simulate writes for the same options, byte for byte", "[sim_host_run]") {
  ScratchDir d("sim_host_run_same");
  // The example (every key at its default) against simulate's defaults; a diff-drive file against the options.
  const fs::path file = d.path / "diff.toml";
  std::ofstream(file) << "seed = 3\nduration_s = 20\n[robot]\nmodel = \"diff-drive\"\n[sensors.landmarks]\n"
                         "ids = \"unknown\"\n[filter]\nstart = \"tracking\"\nparticles = 2000\n[faults]\n"
                         "counts = { \"scan.dropped\" = 7 }\n";
  const fs::path route = d.path / "route.toml";
  std::ofstream(route) << "duration_s = 20\n[world]\nroute = [[5.5, 7.3], [14.5, 7.3, 0.5], [14.5, 10.2], "
                          "[10, 10.5, 1.2], [9, 11.5], [6.8, 11.5], [5.5, 10]]\n[robot]\nmodel = \"velocity\"\n"
                          "[filter]\nsensor_model = \"beam\"\nkld = false\nparticles = 3000\n[faults]\nplan = \"none\"\n";
  struct Pair {
    std::string run, simulate;
  };
  const Pair pairs[] = {
      {"run example", "simulate"},
      {"run '" + file.string() + "'",
       "simulate --robot diff-drive --seed 3 --duration 20 --landmark-ids unknown --start tracking --particles 2000 "
       "--fault scan.dropped=7"},
      {"run '" + route.string() + "'",
       "simulate --robot velocity --duration 20 --faults none --route '5.5,7.3;14.5,7.3,0.5;14.5,10.2;10,10.5,1.2;"
       "9,11.5;6.8,11.5;5.5,10' --sensor-model beam --no-kld --particles 3000"},
  };
  for (const Pair& p : pairs) {
    INFO(p.run);
    REQUIRE(sim_host(p.run + " --no-plots --quiet --out '" + (d.path / "run").string() + "'") == 0);
    REQUIRE(sim_host(p.simulate + " --no-plots --out '" + (d.path / "sim").string() + "'") == 0);
    for (const char* f : {"trajectory.csv", "faults.csv"}) {
      INFO(f);
      CHECK(slurp(d.path / "run" / f) == slurp(d.path / "sim" / f));
    }
    nlohmann::json a = read_json(d.path / "run" / "metrics.json"), b = read_json(d.path / "sim" / "metrics.json");
    CHECK(a["rmse_position_m"] == b["rmse_position_m"]);
    fs::remove_all(d.path / "run");
    fs::remove_all(d.path / "sim");
  }
}

TEST_CASE("a malformed scenario file is refused with FILE:LINE:COLUMN: reason and nothing runs", "[sim_host_run]") {
  ScratchDir d("sim_host_run_refused");
  const fs::path file = d.path / "bad.toml", err = d.path / "err.txt", out = d.path / "out";
  std::ofstream(file) << "seed = 1\n\n[sensors.rangefinder]\nbeams = \"many\"\n";
  CHECK(sim_host("run '" + file.string() + "' --out '" + out.string() + "'", nullptr, err) != 0);
  CHECK(slurp(err) == file.string() + ":4:9: sensors.rangefinder.beams: expected an integer, got a string\n");
  CHECK(!fs::exists(out));
  std::ofstream(file) << "seed = 1\n[robot\n";
  CHECK(sim_host("run '" + file.string() + "' --out '" + out.string() + "'", nullptr, err) != 0);
  CHECK(slurp(err).rfind(file.string() + ":2:", 0) == 0);
  CHECK(!fs::exists(out));
  CHECK(sim_host("run no-such-scenario --out '" + out.string() + "'", nullptr, err) != 0);
  CHECK(slurp(err).find("neither a built-in scenario") != std::string::npos);
}

TEST_CASE("kidnapped: localizes globally, loses the estimate at the kidnapping and regains it", "[sim_host_run]") {
  double wall = 0.0;
  const sim::SimResult r = run_builtin("kidnapped", wall);
  const sim::SimMetrics& m = r.metrics;
  REQUIRE(m.phases.size() == 2);
  CHECK(m.phases[0].localized);
  CHECK(m.phases[0].time_to_localize_s < 5.0);
  CHECK(m.phases[1].lost_at_s >= 12.0);
  CHECK(m.phases[1].localized);
  CHECK(m.phases[1].time_to_localize_s < 4.0);
  CHECK(m.rmse_position_m < 0.10);
  CHECK(wall < 10.0);
}

TEST_CASE("kidnapped with the beam model: nothing random while localized, after the start and the kidnapping, on "
          "held-out seeds",
          "[sim_host_run]") {
  // Issue 37: at most 1 % of the particles drawn while localized are random, after the global start and after the
  // kidnapping, over 20 seeds, the kidnapping regained within 3 s. Before the beam model's recovery origin was its
  // typical hit (BeamRangeFinderModel::log_typical) instead of its peak: 17-21 % and 0-14 % (seeds 1-8). Chosen on
  // seed 1 alone; these are 101-120.
  sim::ScenarioFile f = sim::load_scenario("kidnapped");
  f.filter.range_model = node::RangeModel::beam;
  const sim::SimWorld world = sim::load_world(f.scenario);
  std::uint64_t injected[2] = {0, 0}, drawn[2] = {0, 0};
  double worst_regain = 0.0;
  for (std::uint64_t seed = 101; seed <= 120; ++seed) {
    f.scenario.seed = seed;
    const sim::SimResult r = sim::run_simulation(f.scenario, f.filter, world);
    REQUIRE(r.metrics.phases.size() == 2);
    for (std::size_t k = 0; k < 2; ++k) {
      const sim::PhaseMetrics& p = r.metrics.phases[k];
      INFO("seed " << seed << ", phase " << k << ": localized " << p.localized << " after " << p.time_to_localize_s
                   << " s, injected " << p.injected_particles << " of " << p.drawn_particles);
      CHECK(p.localized);
      injected[k] += p.injected_particles;
      drawn[k] += p.drawn_particles;
    }
    worst_regain = std::max(worst_regain, r.metrics.phases[1].time_to_localize_s);
    CHECK(r.metrics.phases[1].time_to_localize_s <= 3.0);
  }
  const double share[2] = {static_cast<double>(injected[0]) / static_cast<double>(drawn[0]),
                           static_cast<double>(injected[1]) / static_cast<double>(drawn[1])};
  std::printf("kidnapped, beam model, seeds 101-120: random while localized %.3f %% after the start, %.3f %% after the "
              "kidnapping; regained within %.1f s at worst\n",
              100.0 * share[0], 100.0 * share[1], worst_regain);
  CHECK(share[0] <= 0.01);
  CHECK(share[1] <= 0.01);
}

TEST_CASE("a lost filter searches: every range model leaves a confident wrong belief (held-out seeds)",
          "[sim_host_run]") {
  // Issue 37: started as a Gaussian (0.2 m, 0.1 rad) around a pose the robot is not at (wrong_start_pose: the
  // route's pose half the run later, 3 m or more away), the filter's first scans fit badly, recovery injects and the
  // robot is found. Every range model of MCL: the likelihood field and the beam model on the differential drive
  // (kidnapped, the kidnapping off), the steered model on the handlebar bicycle. Measured (seeds 101-110, nothing
  // tuned on them): at worst 3.3 s, 5.4 s and 1.6 s; bounded here at 6, 8 and 5 s.
  struct Case {
    const char* scenario;
    node::RangeModel model;
    double within_s;
  };
  const Case cases[] = {{"kidnapped", node::RangeModel::likelihood_field, 6.0},
                        {"kidnapped", node::RangeModel::beam, 8.0},
                        {"bicycle-rangefinder-global", node::RangeModel::steered, 5.0}};
  for (const Case& c : cases) {
    sim::ScenarioFile f = sim::load_scenario(c.scenario);
    f.filter.range_model = c.model;
    f.filter.start = sim::StartKind::wrong;
    f.scenario.kidnap_at_s = -1.0;
    const sim::SimWorld world = sim::load_world(f.scenario);
    double worst = 0.0;
    for (std::uint64_t seed = 101; seed <= 110; ++seed) {
      f.scenario.seed = seed;
      const sim::SimResult r = sim::run_simulation(f.scenario, f.filter, world);
      const sim::PhaseMetrics& p = r.metrics.phases.at(0);
      INFO(c.scenario << ", " << node::to_string(c.model) << ", seed " << seed << ": localized " << p.localized
                      << " after " << p.time_to_localize_s << " s");
      CHECK(p.name == "wrong start");
      CHECK(p.localized);
      CHECK(p.time_to_localize_s <= c.within_s);
      worst = std::max(worst, p.time_to_localize_s);
    }
    std::printf("wrong start, %s, %s: 10 / 10 seeds found, within %.1f s at worst\n", c.scenario,
                node::to_string(c.model), worst);
  }
}

TEST_CASE("bicycle-rangefinder: the steered model tracks the handlebar rangefinder without a steering sensor",
          "[sim_host_run]") {
  double wall = 0.0;
  const sim::SimResult r = run_builtin("bicycle-rangefinder", wall);
  CHECK(r.metrics.phases.at(0).localized);
  CHECK(r.metrics.rmse_position_m < 0.10);
  CHECK(r.metrics.rmse_heading_deg < 3.0);
  CHECK(wall < 10.0);
}

// Issue 37: the handlebar rangefinder from a uniform start. The split (steered_scan.hpp) and the reading's floor were
// chosen on seeds 1-10; these seeds were never looked at while tuning. Localized (0.5 m, 10 deg, held 2 s) within
// 10 s in at least 19 of 20, heading RMSE once localized at most 2 deg over the seeds (each at most 3), and at most
// 0.01 % random particles drawn once localized. Without the per-particle modes none localizes (heading 20-45 deg off).
TEST_CASE("bicycle-rangefinder-global: the handlebar rangefinder localizes from a uniform start on held-out seeds",
          "[sim_host_run]") {
  for (const bool sensor : {false, true}) {
    sim::ScenarioFile f = sim::load_scenario("bicycle-rangefinder-global");
    REQUIRE(f.filter.start == sim::StartKind::global);
    f.scenario.steering_sensor = sensor;  // present: biased, as the scenario's default steering sensor (0.5 deg)
    const sim::SimWorld world = sim::load_world(f.scenario);
    int within = 0;
    double sum_sq = 0.0;
    int localized = 0;
    std::uint64_t injected = 0, drawn = 0;
    for (std::uint64_t seed = 101; seed <= 120; ++seed) {
      f.scenario.seed = seed;
      const sim::SimResult r = sim::run_simulation(f.scenario, f.filter, world);
      const sim::PhaseMetrics& p = r.metrics.phases.at(0);
      INFO("steering sensor " << sensor << ", seed " << seed << ": localized at " << p.localized_at_s
                              << " s, heading RMSE " << r.metrics.rmse_heading_deg << " deg");
      if (p.localized && p.localized_at_s <= 10.0) ++within;
      if (p.localized) {
        ++localized;
        sum_sq += r.metrics.rmse_heading_deg * r.metrics.rmse_heading_deg;
        CHECK(r.metrics.rmse_heading_deg <= 3.0);
        injected += p.injected_particles;
        drawn += p.drawn_particles;
      }
    }
    const double rmse = localized > 0 ? std::sqrt(sum_sq / localized) : 1e9;
    std::printf("bicycle-rangefinder-global, steering sensor %s: %d / 20 localized within 10 s, heading RMSE %.2f deg, "
                "%llu injected once localized\n",
                sensor ? "present" : "absent", within, rmse, static_cast<unsigned long long>(injected));
    CHECK(within >= 19);
    CHECK(rmse <= 2.0);
    // Asked: none. Measured: 2 of 20 seeds without the sensor draw 47 and 84 of ~200000 (0.02-0.04 %) at a handle
    // change; held here at most 0.01 % over the seeds (issue 37's closing note).
    CHECK(static_cast<double>(injected) <= 1.0e-4 * static_cast<double>(drawn));
  }
}

TEST_CASE("omni-velocity: the mecanum base driving sideways localizes globally through its faults", "[sim_host_run]") {
  double wall = 0.0;
  const sim::SimResult r = run_builtin("omni-velocity", wall);
  CHECK(r.metrics.phases.at(0).localized);
  CHECK(r.metrics.rmse_position_m < 0.10);
  CHECK(wall < 10.0);
}

TEST_CASE("diffdrive-script: the robot on its control script shuttles along the corridor and is localized",
          "[sim_host_run]") {
  double wall = 0.0;
  const sim::SimResult r = run_builtin("diffdrive-script", wall);
  // East 12 m from x = 3 (20 s at 0.6 m/s), a half turn, back west, a half turn, east again for 2.3 s.
  double x_max = 0.0, x_back = 100.0, y_min = 100.0, y_max = 0.0;
  for (const auto& p : r.stream.truth) {
    const double t = static_cast<double>(p.t_ns - r.stream.truth.front().t_ns) * 1e-9;
    const double x = static_cast<double>(p.pose.x), y = static_cast<double>(p.pose.y);
    x_max = std::max(x_max, x);
    if (t > 30.0) x_back = std::min(x_back, x);
    y_min = std::min(y_min, y), y_max = std::max(y_max, y);
  }
  const double x_end = static_cast<double>(r.stream.truth.back().pose.x);
  std::printf("diffdrive-script: x from 3.0 to %.2f and back to %.2f m, ends at %.2f m; y in [%.2f, %.2f] m\n", x_max,
              x_back, x_end, y_min, y_max);
  CHECK(x_max == Approx(15.0).margin(0.3));
  CHECK(x_back == Approx(3.0).margin(0.3));
  CHECK(x_end == Approx(3.0 + 0.6 * (50.0 - 47.68)).margin(0.3));
  CHECK(y_min > 6.3);  // in the corridor, clear of its walls (6.1 and 8.5)
  CHECK(y_max < 8.3);
  CHECK(r.stream.kidnap_ns < 0);
  CHECK(r.metrics.phases.at(0).localized);
  CHECK(r.metrics.rmse_position_m < 0.10);
  CHECK(wall < 10.0);
}

TEST_CASE("the team scenarios run through sim_host run's runner within their accuracy", "[sim_host_run]") {
  ScratchDir d("sim_host_run_team");
  struct Case {
    const char* name;
    double duration_s, rmse_m;
  };
  // Measured at seed 1: worst robot 0.114 m (coop-slam), 0.074 m (coop-slam-team), 0.036 m (diffdrive-landmarks).
  for (const Case c : {Case{"coop-slam", 60.0, 0.20}, Case{"coop-slam-team", 60.0, 0.15},
                       Case{"diffdrive-landmarks", 60.0, 0.10}}) {
    INFO(c.name);
    sim::ScenarioFile f = sim::load_scenario(c.name);
    REQUIRE(f.runner == sim::ScenarioRunner::team);
    f.team_duration_s = c.duration_s;
    const fs::path out = d.path / c.name;
    const auto t0 = std::chrono::steady_clock::now();
    sim::run_scenario(f, sim::RunOptions{out.string(), false, true});
    const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const nlohmann::json j = read_json(out / "metrics.json");
    double worst = 0.0;
    if (j.contains("shared")) {
      for (const auto& r : j["shared"]["per_robot"]) worst = std::max(worst, r["position_rmse_m"].get<double>());
    } else {  // diffdrive-landmarks
      CHECK(j["all_localized"].get<bool>());
      for (const auto& r : j["robots"]) worst = std::max(worst, r["position_rmse_m"].get<double>());
    }
    std::printf("%s, %.0f s: worst robot's position RMSE %.3f m, %.1f s wall\n", c.name, c.duration_s, worst, wall);
    CHECK(worst > 0.0);
    CHECK(worst < c.rmse_m);
  }
}

TEST_CASE("bicycle-exercise: the five cases' clouds through sim_host run's runner", "[sim_host_run]") {
  ScratchDir d("sim_host_run_exercise");
  sim::ScenarioFile f = sim::load_scenario("bicycle-exercise");
  REQUIRE(f.runner == sim::ScenarioRunner::exercise);
  f.exercise_samples = 500;
  sim::run_scenario(f, sim::RunOptions{d.path.string(), false, true});
  for (int k = 1; k <= 5; ++k) {
    const fs::path csv = d.path / ("case" + std::to_string(k) + ".csv");
    INFO(csv);
    REQUIRE(fs::exists(csv));
    const std::string text = slurp(csv);
    CHECK(std::count(text.begin(), text.end(), '\n') == 501);  // header and 500 samples
  }
}

TEST_CASE("a scenario's landmark file replaces the office's posts, and the EKF tracks on it", "[sim_host_run]") {
  ScratchDir d("sim_host_run_landmarks");
  // Six posts of our own (none of the office's), signatures 1..6, in the office's free space along its route.
  std::ofstream(d.path / "posts.csv") << "# x,y,signature\n4,7.8,1\n9,7,2\n13,7.9,3\n15.5,9.5,4\n11.5,11.5,5\n"
                                         "7,10,6\n";
  std::ofstream(d.path / "posts.toml") << "duration_s = 30\n[world]\nlandmarks = \"posts.csv\"\n"
                                          "[robot]\nmodel = \"diff-drive\"\n[filter]\ntype = \"ekf\"\n"
                                          "[faults]\nplan = \"none\"\nburst_at_s = -1\n";
  const sim::ScenarioFile f = sim::load_scenario((d.path / "posts.toml").string());
  CHECK(f.scenario.landmarks_csv == (d.path / "posts.csv").string());
  const sim::SimWorld world = sim::load_world(f.scenario);
  REQUIRE(world.landmarks.size() == 6);
  const sim::SimResult r = sim::run_simulation(f.scenario, f.filter, world);
  std::printf("EKF on a landmark file: %u sightings fused, position RMSE %.3f m\n", r.ekf.accepted,
              r.metrics.rmse_position_m);
  CHECK(r.metrics.phases.at(0).localized);
  CHECK(r.metrics.rmse_position_m < 0.15);
}

TEST_CASE("a route's waypoint speeds drive its segments at those speeds", "[sim_host_run]") {
  // The office's route at the cruise speed, and again with every segment at half of it.
  const std::string route = "[[5.5, 7.3{s}], [14.5, 7.3{s}], [14.5, 10.2{s}], [10.0, 10.5{s}], [9.0, 11.5{s}], "
                            "[6.8, 11.5{s}], [5.5, 10.0{s}]]";
  double travelled[2] = {0.0, 0.0};
  for (int slow = 0; slow < 2; ++slow) {
    std::string r = route;
    for (std::size_t at; (at = r.find("{s}")) != std::string::npos;) r.replace(at, 3, slow ? ", 0.4" : "");
    const sim::ScenarioFile f = sim::parse_scenario(
        "duration_s = 20\n[world]\nroute = " + r + "\n[robot]\nmodel = \"diff-drive\"\nspeed_mps = 0.8\n"
        "[filter]\nstart = \"tracking\"\n[faults]\nplan = \"none\"\nkidnap_at_s = -1\nburst_at_s = -1\n", "speeds.toml");
    const sim::SimWorld world = sim::load_world(f.scenario);
    const sim::SimResult res = sim::run_simulation(f.scenario, f.filter, world);
    for (std::size_t i = 1; i < res.stream.truth.size(); ++i)
      travelled[slow] += static_cast<double>(std::hypot(res.stream.truth[i].pose.x - res.stream.truth[i - 1].pose.x,
                                                        res.stream.truth[i].pose.y - res.stream.truth[i - 1].pose.y));
    CHECK(res.metrics.rmse_position_m < 0.10);
  }
  std::printf("20 s at 0.8 m/s: %.2f m; every segment at 0.4 m/s: %.2f m\n", travelled[0], travelled[1]);
  CHECK(travelled[1] / travelled[0] == Approx(0.5).margin(0.05));
}

TEST_CASE("a control script drives the robot: constant commands trace the analytic circle, or line, of each model",
          "[sim_host_run]") {
  // From (11.5, 9, 0) in the office's north-east room, 20 s of one command held: the body twist (v1, v2, w) turns
  // the reference point about a fixed centre, R(theta0) (-v2/w, v1/w) from the start, at radius |(v1, v2)| / |w|;
  // the holonomic robot (no turn) goes straight. The truth is the models' own noisy sample of each 10 ms step, so it
  // wanders off the analytic path by its noise (and the diff drive's by its rounding to whole ticks).
  struct Case {
    const char* model;
    const char* command;  // the script's one command's terms
    double v1, v2, w;     // its body twist
    double radial_m, final_m;  // bounds: the largest distance from the circle, and from the analytic final pose
  };
  const double length = static_cast<double>(sim::robot_models().truth.bicycle.frame_length);
  const double steer = std::asin(length / 1.5);  // the front wheel on a 1.5 m circle
  char bicycle[64];
  std::snprintf(bicycle, sizeof bicycle, "0.6, %.9f", steer);
  // The diff drive's twist as whole encoder ticks per 10 ms step (70 left, 86 right: 0.598 m/s, 0.409 rad/s), since
  // its wheels carry no other: then the circle is the commanded one.
  const est::DiffDriveParams dd = sim::robot_models().truth.diff_drive;
  const double mpt = static_cast<double>(est::diff_drive_m_per_tick(dd)), track = static_cast<double>(dd.track_width);
  const double dd_v = 0.5 * (70.0 + 86.0) * mpt / 0.01, dd_w = (86.0 - 70.0) * mpt / (track * 0.01);
  char diff_drive[64];
  std::snprintf(diff_drive, sizeof diff_drive, "%.9f, %.9f", dd_v, dd_w);
  const Case cases[] = {
      {"velocity", "0.6, 0.4", 0.6, 0.0, 0.4, 0.05, 0.10},
      {"diff-drive", diff_drive, dd_v, 0.0, dd_w, 0.10, 0.25},
      {"bicycle", bicycle, 0.6 * std::cos(steer), 0.6 * std::sin(steer), 0.6 * std::sin(steer) / length, 0.10, 0.25},
      {"omni", "0.5, 0.2, 0.35", 0.5, 0.2, 0.35, 0.10, 0.25},
      {"holonomic", "0.1, 0.1", 0.1, 0.1, 0.0, 0.10, 0.25},
  };
  for (const Case& c : cases) {
    INFO(c.model);
    const sim::ScenarioFile f = sim::parse_scenario(
        std::string("duration_s = 20\n[robot]\nmodel = \"") + c.model +
            "\"\nstart_pose = [11.5, 9.0, 0.0]\ncontrols = [[0, " + c.command +
            "]]\n[filter]\nstart = \"tracking\"\nparticles = 1000\nkld = false\n[faults]\nplan = \"none\"\n"
            "burst_at_s = -1\n",
        "script.toml");
    const sim::SimWorld world = sim::load_world(f.scenario);
    const sim::SimResult res = sim::run_simulation(f.scenario, f.filter, world);
    const auto& truth = res.stream.truth;
    REQUIRE(truth.size() == 2000);
    const double x0 = 11.5, y0 = 9.0;
    const double cx = x0 - c.v2 / (c.w != 0.0 ? c.w : 1.0), cy = y0 + c.v1 / (c.w != 0.0 ? c.w : 1.0);
    const double radius = std::hypot(c.v1, c.v2) / std::fabs(c.w != 0.0 ? c.w : 1.0);
    // The analytic pose at t: the start's offset from the centre turned by w t (or the line at the twist).
    const auto analytic = [&](double t, double& x, double& y) {
      if (c.w == 0.0) {
        x = x0 + c.v1 * t, y = y0 + c.v2 * t;
        return;
      }
      const double ox = x0 - cx, oy = y0 - cy, a = c.w * t;
      x = cx + ox * std::cos(a) - oy * std::sin(a), y = cy + ox * std::sin(a) + oy * std::cos(a);
    };
    double radial = 0.0;
    for (const auto& p : truth) {
      const double t = static_cast<double>(p.t_ns - truth.front().t_ns) * 1e-9;
      double ax = 0.0, ay = 0.0;
      analytic(t, ax, ay);
      const double px = static_cast<double>(p.pose.x), py = static_cast<double>(p.pose.y);
      const double off = c.w != 0.0 ? std::fabs(std::hypot(px - cx, py - cy) - radius)
                                    // the line's normal distance
                                    : std::fabs((px - x0) * c.v2 - (py - y0) * c.v1) / std::hypot(c.v1, c.v2);
      radial = std::max(radial, off);
    }
    const auto& last = truth.back();
    const double t_end = static_cast<double>(last.t_ns - truth.front().t_ns) * 1e-9;
    double ax = 0.0, ay = 0.0;
    analytic(t_end, ax, ay);
    const double final_m = std::hypot(static_cast<double>(last.pose.x) - ax, static_cast<double>(last.pose.y) - ay);
    const double heading_err = std::remainder(static_cast<double>(last.pose.theta) - c.w * t_end, 2.0 * M_PI);
    std::printf("control script, %s [%s] for %.2f s: %s %.3f m, final pose %.3f m and %.2f deg off the analytic; "
                "filter RMSE %.3f m\n",
                c.model, c.command, t_end, c.w != 0.0 ? "off the circle by at most" : "off the line by at most", radial,
                final_m, heading_err * 180.0 / M_PI, res.metrics.rmse_position_m);
    CHECK(radial < c.radial_m);
    CHECK(final_m < c.final_m);
    CHECK(std::fabs(heading_err) < 0.1);
    CHECK(res.metrics.rmse_position_m < 0.10);  // and the filter follows it
  }
}

TEST_CASE("a rangefinder mounted off the reference point, and a narrow landmark sensor, are what the filters see",
          "[sim_host_run]") {
  // The rangefinder 0.2 m ahead and 0.1 m left of the axle midpoint, turned 0.5 rad: MCL is told the mount.
  const sim::ScenarioFile f = sim::parse_scenario(
      "duration_s = 20\n[robot]\nmodel = \"diff-drive\"\n[sensors.rangefinder]\nbase_pose = [0.2, 0.1, 0.5]\n"
      "[filter]\nstart = \"tracking\"\n[faults]\nplan = \"none\"\nkidnap_at_s = -1\nburst_at_s = -1\n",
      "mount.toml");
  const sim::SimWorld world = sim::load_world(f.scenario);
  const sim::SimResult r = sim::run_simulation(f.scenario, f.filter, world);
  CHECK(r.stream.mount.theta == 0.5f);
  std::printf("rangefinder at (0.2, 0.1, 0.5 rad): position RMSE %.3f m\n", r.metrics.rmse_position_m);
  CHECK(r.metrics.rmse_position_m < 0.10);
  // A landmark sensor that sees 90 deg ahead: fewer sightings than the full turn, the EKF still tracks.
  std::uint32_t fused[2] = {0, 0};
  for (int narrow = 0; narrow < 2; ++narrow) {
    const sim::ScenarioFile e = sim::parse_scenario(
        std::string("duration_s = 30\n[robot]\nmodel = \"diff-drive\"\n[sensors.landmarks]\nfov_deg = ") +
            (narrow ? "90" : "360") + "\n[filter]\ntype = \"ekf\"\n[faults]\nplan = \"none\"\nburst_at_s = -1\n",
        "fov.toml");
    const sim::SimResult re = sim::run_simulation(e.scenario, e.filter, world);
    fused[narrow] = re.ekf.accepted;
    CHECK(re.metrics.rmse_position_m < 0.15);
  }
  std::printf("landmark features fused: %u over 360 deg, %u over 90 deg\n", fused[0], fused[1]);
  CHECK(fused[1] < fused[0] / 2);
}

TEST_CASE("a run's LCM log holds its inputs, the ground truth and its estimates, and estimator_node's replay of it "
          "gives the same estimates bit for bit", "[sim_host_run]") {
  ScratchDir d("sim_host_run_log");
  sim::ScenarioFile f = sim::load_scenario("kidnapped");
  f.scenario.duration_s = 15.0;  // the kidnapping at 12 s and the recovery after it
  sim::run_scenario(f, sim::RunOptions{d.path.string(), false, true});
  const fs::path log = d.path / "run.lcmlog";
  REQUIRE(fs::exists(log));
  const nlohmann::json side = read_json(d.path / "run.lcmlog.json");
  const std::vector<est_lcm::pose_estimate_t> logged = est::test::read_estimates(log.string());
  CHECK(logged.size() == 1500u);  // 15 s of a 100 Hz loop
  CHECK(side["messages"]["EST_POSE"].get<int>() == 1500);
  CHECK(side["messages"]["EST_GROUND_TRUTH"].get<int>() > 1400);
  CHECK(side["messages"]["EST_RANGE_SCAN"].get<int>() > 140);
  // The sidecar's options replay the log (its inputs only) through estimator_node: the same estimates.
  const fs::path replayed = d.path / "replayed.lcmlog";
  const std::string cmd = std::string("'") + ESTIMATOR_NODE_EXE + "' " + side["estimator_node_options"].get<std::string>() +
                          " --out '" + replayed.string() + "' --quiet";
  REQUIRE(est::test::run_command(cmd, (d.path / "node.txt").string()) == 0);
  const std::vector<est_lcm::pose_estimate_t> again = est::test::read_estimates(replayed.string());
  INFO(slurp(d.path / "node.txt"));
  CHECK(again.size() == logged.size());
  CHECK(est::test::first_difference(logged, again) == -1);
}
