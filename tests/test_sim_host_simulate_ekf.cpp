// sim_host simulate --filter ekf: the office's landmark sightings through the HAL gate into the firmware's EKF
// (est::loop::EkfEstimator through est::loop::ConfiguredLoop). Tracking accuracy and consistency within stated
// bounds for both robots, with known and unknown correspondences; every injected landmark fault counted with its
// reason; finite estimates; bit-identical repeats; the landmark stream leaves MCL's estimates alone; bad
// configurations refused.
#include <sys/wait.h>
#include <unistd.h>

#include <catch2/catch.hpp>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "scratch_dir.hpp"
#include "sim/scenario.hpp"
#include "sim/sensor_stream.hpp"
#include "sim/simulate.hpp"

#ifndef SIM_HOST_EXE
#error "SIM_HOST_EXE must name the sim_host executable"
#endif

namespace {

namespace fs = std::filesystem;
constexpr double kPi = 3.14159265358979323846;

// Under the sanitizers (host-debug) the runs are shorter; the bounds stay the same.
#if defined(__SANITIZE_ADDRESS__)
constexpr double kRunSeconds = 8.0;
#else
constexpr double kRunSeconds = 20.0;
#endif

// Every fault class of every stream the robot has, once, and a 0.3 s bus outage.
sim::ScenarioConfig ekf_scenario(sim::RobotKind robot, std::uint64_t seed, bool ids_known) {
  sim::ScenarioConfig c;
  c.robot = robot;
  c.seed = seed;
  c.duration_s = kRunSeconds;
  c.kidnap_at_s = -1.0;
  c.burst_at_s = kRunSeconds / 2.0 - 1.0;
  c.burst_ms = 300.0;
  c.landmark_ids_known = ids_known;
  for (const sim::FaultClassInfo& f : sim::fault_catalogue())
    if (sim::fault_applies(robot, f.key)) c.faults[f.key] = 1;
  return c;
}

sim::FilterOptions ekf_filter() {
  sim::FilterOptions f;
  f.filter = est::loop::Filter::ekf;
  f.start = sim::StartKind::tracking;
  return f;
}

float wrap(float a) { return std::remainder(a, 6.28318530717958647692f); }

struct Consistency {
  double heading_within_3sigma = 0.0;   // share of outputs
  double position_within_3sigma = 0.0;  // (ex/sx)^2 + (ey/sy)^2 < 9 + margin: see below
};

Consistency consistency(const sim::SimResult& r) {
  std::size_t h = 0, p = 0;
  for (const sim::OutputRow& row : r.rows) {
    const double eh = wrap(row.estimate.theta - row.truth.theta);
    if (std::fabs(eh) < 3.0 * static_cast<double>(row.sigma_theta_rad)) ++h;
    // Mahalanobis distance of the position error under the full 2 x 2 covariance.
    const double a = static_cast<double>(row.sigma_x_m) * static_cast<double>(row.sigma_x_m);
    const double c = static_cast<double>(row.sigma_y_m) * static_cast<double>(row.sigma_y_m);
    const double b = static_cast<double>(row.cov_xy_m2);
    const double ex = static_cast<double>(row.estimate.x - row.truth.x);
    const double ey = static_cast<double>(row.estimate.y - row.truth.y);
    const double det = a * c - b * b;
    const double d2 = det > 0.0 ? (c * ex * ex - 2.0 * b * ex * ey + a * ey * ey) / det : 1e9;
    if (d2 < 11.83) ++p;  // chi-square, 2 dof, 99.73 % (the 2-D "3 sigma")
  }
  const double n = static_cast<double>(std::max<std::size_t>(1u, r.rows.size()));
  return {static_cast<double>(h) / n, static_cast<double>(p) / n};
}

bool all_finite(const sim::SimResult& r) {
  for (const sim::OutputRow& row : r.rows)
    if (!std::isfinite(row.estimate.x) || !std::isfinite(row.estimate.y) || !std::isfinite(row.estimate.theta) ||
        !std::isfinite(row.sigma_x_m) || !std::isfinite(row.sigma_y_m) || !std::isfinite(row.sigma_theta_rad))
      return false;
  return true;
}

using est::test::slurp;

struct TempDir : est::test::ScratchDir {
  explicit TempDir(const std::string& tag) : ScratchDir("sim_host_simulate_ekf_" + tag) {}
};

}  // namespace

TEST_CASE("the EKF tracks on landmark sightings through every fault class, known or unknown ids", "[simulate][ekf]") {
  // Stated bounds: position RMSE 6 cm, heading RMSE 2 deg, never beyond 0.5 m (the 0.3 s outage leaves the
  // estimate standing while the robot drives 0.24 m). Measured over 60 s, seeds 1-3, both robots, both id modes:
  // 2.2-2.5 cm and 0.66-0.79 deg, max 0.30 m. The sensor: 5 cm / 0.02 rad, posts within 6 m in line of sight at
  // 5 Hz. Consistency: at least 95 % of the outputs within the filter's own 3 sigma in heading (measured 100 %), and
  // 90 % within its 2-D 99.7 % ellipse in position (measured 94-97 %): the misses are the wheel-slip episodes (the
  // encoders count 30 % more for 0.5 s) and the outage (the HAL re-baselines the encoders after the gap, so 0.3 s
  // of motion never reaches the filter), disturbances the odometry model does not describe; the landmarks pull the
  // estimate back within ~1 s.
  for (const sim::RobotKind robot : {sim::RobotKind::bicycle, sim::RobotKind::diff_drive}) {
    for (const bool known : {true, false}) {
      const sim::ScenarioConfig sc = ekf_scenario(robot, 11, known);
      const sim::SimResult r = sim::run_simulation(sc, ekf_filter(), sim::load_world(sc));
      const sim::SimMetrics& m = r.metrics;
      const Consistency k = consistency(r);
      std::printf("simulate --filter ekf %s, ids %s, %.0f s, every fault class: position RMSE %.3f m (max %.3f), "
                  "heading RMSE %.2f deg (max %.2f); within 3 sigma: heading %.3f, position %.3f; %u features fused, "
                  "%u refused\n",
                  sim::to_string(robot), known ? "known" : "unknown", kRunSeconds, m.rmse_position_m,
                  m.max_position_error_m, m.rmse_heading_deg, m.max_heading_error_deg, k.heading_within_3sigma,
                  k.position_within_3sigma, r.ekf.accepted, r.ekf.rejected());
      INFO(sim::to_string(robot) << ", ids " << (known ? "known" : "unknown"));
      CHECK(r.filter == est::loop::Filter::ekf);
      REQUIRE(m.phases.size() == 1u);
      CHECK(m.phases[0].localized);
      CHECK(m.rmse_position_m < 0.06);
      CHECK(m.rmse_heading_deg < 2.0);
      CHECK(m.max_position_error_m < 0.5);
      CHECK(k.heading_within_3sigma > 0.95);
      CHECK(k.position_within_3sigma > 0.90);
      CHECK(all_finite(r));
      CHECK(r.nonfinite_estimates == 0u);
      // At 5 Hz with ~4 posts in view, most features are fused; scans are counted as unused, never as faults.
      CHECK(r.ekf.accepted > static_cast<std::uint32_t>(kRunSeconds * 5.0 * 2.0));
      CHECK(r.ekf.rejected() * 50u < r.ekf.accepted);
      CHECK(r.loop.unused > 0u);
      for (const sim::OutputRow& row : r.rows) REQUIRE(row.particles == 0u);
    }
  }
}

TEST_CASE("every injected landmark fault is counted once with its reason, under the EKF and under MCL", "[simulate][ekf]") {
  for (const sim::RobotKind robot : {sim::RobotKind::bicycle, sim::RobotKind::diff_drive}) {
    const sim::ScenarioConfig sc = ekf_scenario(robot, 7, false);
    const sim::SimWorld world = sim::load_world(sc);
    const sim::SimResult r = sim::run_simulation(sc, ekf_filter(), world);
    const auto expected = r.stream.expected_counts();
    const auto observed = r.observed_counts();
    INFO(sim::to_string(robot));
    for (const char* k : {"hal.landmarks.duplicate", "hal.landmarks.stale", "hal.landmarks.from_future",
                          "hal.landmarks.not_finite", "hal.landmarks.out_of_range"})
      CHECK(expected.at(k) == 1);
    // The late sighting is too old for the loop once per feature; the late scan is not the EKF's (unused).
    int late_features = 0;
    for (const sim::InjectedFault& f : r.stream.faults)
      if (f.key == "landmarks.late") late_features = f.amount;
    CHECK(late_features >= 2);
    CHECK(expected.at("loop.too_old") == late_features);
    CHECK(observed == expected);
    CHECK(r.sensor_faults.at("landmarks").total() == 5u);

    // MCL drops the sightings when they are pushed (unused), before the loop's ordering: the late sighting moves no
    // counter there, the late scan does, and the HAL counts the same landmark faults.
    sim::FilterOptions mcl;
    mcl.start = sim::StartKind::tracking;
    mcl.particles = 50;
    mcl.kld = false;
    mcl.beam_stride = 36;
    const sim::SimResult m = sim::run_simulation(sc, mcl, world);
    CHECK(m.stream.expected_counts().at("loop.too_old") == 1);
    CHECK(m.observed_counts() == m.stream.expected_counts());
    CHECK(m.sensor_faults.at("landmarks").total() == 5u);
  }
}

TEST_CASE("the same seed gives bit-identical EKF outputs, another seed does not", "[simulate][ekf]") {
  TempDir dir("repeat");
  std::string csv[3];
  const std::uint64_t seeds[3] = {3, 3, 4};
  for (int i = 0; i < 3; ++i) {
    const sim::ScenarioConfig sc = ekf_scenario(sim::RobotKind::bicycle, seeds[i], false);
    const sim::FilterOptions fo = ekf_filter();
    const sim::SimWorld world = sim::load_world(sc);
    const sim::SimResult r = sim::run_simulation(sc, fo, world);
    const fs::path d = dir.path / std::to_string(i);
    sim::write_simulation_outputs(r, sc, fo, world, d.string(), false);
    csv[i] = slurp(d / "trajectory.csv");
    const nlohmann::json j = nlohmann::json::parse(slurp(d / "metrics.json"));
    CHECK(j.at("filter").at("kind") == "ekf");
    CHECK(j.at("ekf").at("features_fused").get<std::uint32_t>() == r.ekf.accepted);
    CHECK(j.at("faults").at("every_injected_fault_counted_with_its_reason").get<bool>());
  }
  REQUIRE(csv[0].size() > 10000u);
  CHECK(csv[0] == csv[1]);
  CHECK(csv[0] != csv[2]);
}

TEST_CASE("the landmark stream and its faults leave MCL's estimates unchanged", "[simulate][ekf]") {
  // Sightings and their faults draw from their own generators and MCL drops sightings unused: the estimates of a
  // run with landmark faults are those of the same run without them (only the reject count columns differ).
  sim::ScenarioConfig with = ekf_scenario(sim::RobotKind::diff_drive, 5, true);
  with.burst_at_s = -1.0;
  sim::ScenarioConfig without = with;
  for (auto& [key, n] : without.faults)
    if (key.rfind("landmarks.", 0) == 0) n = 0;
  sim::FilterOptions mcl;
  mcl.start = sim::StartKind::tracking;
  mcl.particles = 100;
  mcl.kld = false;
  mcl.beam_stride = 18;
  const sim::SimWorld world = sim::load_world(with);
  const sim::SimResult a = sim::run_simulation(with, mcl, world);
  const sim::SimResult b = sim::run_simulation(without, mcl, world);
  REQUIRE(a.rows.size() == b.rows.size());
  bool same = true;
  for (std::size_t i = 0; i < a.rows.size(); ++i)
    same = same && a.rows[i].t_ns == b.rows[i].t_ns && a.rows[i].estimate.x == b.rows[i].estimate.x &&
           a.rows[i].estimate.y == b.rows[i].estimate.y && a.rows[i].estimate.theta == b.rows[i].estimate.theta;
  CHECK(same);
  CHECK(a.sensor_faults.at("landmarks").total() == 5u);
  CHECK(b.sensor_faults.at("landmarks").total() == 0u);
  CHECK(a.stream.truth.back().pose.x == b.stream.truth.back().pose.x);
}

TEST_CASE("the EKF is refused a global start and a world without landmarks", "[simulate][ekf]") {
  sim::ScenarioConfig sc = ekf_scenario(sim::RobotKind::bicycle, 1, true);
  sc.duration_s = 3.0;
  sc.faults.clear();
  sim::FilterOptions global = ekf_filter();
  global.start = sim::StartKind::global;
  sim::SimWorld world = sim::load_world(sc);
  CHECK_THROWS_AS(sim::run_simulation(sc, global, world), std::invalid_argument);
  world.landmarks = est::LandmarkMap();  // as a ROS map: no landmarks
  CHECK_THROWS_AS(sim::run_simulation(sc, ekf_filter(), world), std::invalid_argument);
  // Without landmarks the stream has no sightings, and landmark faults cannot be placed.
  sim::FilterOptions mcl;
  mcl.start = sim::StartKind::tracking;
  mcl.particles = 50;
  const sim::SimResult r = sim::run_simulation(sc, mcl, world);
  CHECK(r.stream.sightings.empty());
  sc.faults["landmarks.nan"] = 1;
  CHECK_THROWS_AS(sim::generate_stream(sc, world), std::invalid_argument);
}

TEST_CASE("sim_host simulate --filter ekf runs from the command line and rejects what it cannot do", "[simulate][ekf]") {
  TempDir dir("cli");
  const auto run = [](const std::string& args) {
    const std::string cmd = std::string("'") + SIM_HOST_EXE + "' " + args + " > /dev/null 2>&1";
    const int rc = std::system(cmd.c_str());
    return WIFEXITED(rc) ? WEXITSTATUS(rc) : -1;
  };
  const fs::path out = dir.path / "run";
  REQUIRE(run("simulate --out '" + out.string() + "' --filter ekf --robot diff-drive --duration 4 --landmark-ids unknown "
              "--no-plots --faults none --fault landmarks.nan=1") == 0);
  const nlohmann::json j = nlohmann::json::parse(slurp(out / "metrics.json"));
  CHECK(j.at("filter").at("kind") == "ekf");
  CHECK(j.at("filter").at("start") == "tracking");
  CHECK(j.at("scenario").at("landmark_ids") == "unknown");
  CHECK(j.at("scenario").at("kidnap_at_s").get<double>() < 0.0);  // no kidnapping by default with the EKF
  CHECK(j.at("phases").size() == 1u);
  CHECK(j.at("faults").at("rejects_by_counter").at("hal.landmarks.not_finite").at("counted") == 1);
  CHECK(run("simulate --out '" + out.string() + "' --filter ekf --start global --duration 2") != 0);
  CHECK(run("simulate --out '" + out.string() + "' --filter ekf --landmark-hz 7 --duration 2") != 0);
  CHECK(run("simulate --out '" + out.string() + "' --filter kalman --duration 2") != 0);
  CHECK(run("simulate --out '" + out.string() + "' --landmark-ids maybe --duration 2") != 0);
}
