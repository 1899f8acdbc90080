// sim_host simulate --scenario coop-slam and coop-slam-team end to end, as a user runs them: the cooperative
// EKF-SLAM exercise and a team of four, each robot's node in process. Sharing z and u must beat each robot's own
// measurements alone, the shared estimate must be consistent (NEES), every node must hold the same estimate, and
// the files the network test and estimator_node need (the per-robot logs, the node options) must be written. The
// run's one log (run.lcmlog) replays through each robot's team node (estimator_node --filter coop-ekf --replay) to the
// run's estimates, bit for bit, and holds every robot's truth and estimate.
#include <sys/wait.h>

#include <catch2/catch.hpp>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <lcm/lcm-cpp.hpp>
#include <map>
#include <nlohmann/json.hpp>
#include <string>

#include "scratch_dir.hpp"

#include <est_lcm/ground_truth_t.hpp>
#include <est_lcm/pose_estimate_t.hpp>

#ifndef SIM_HOST_EXE
#error "SIM_HOST_EXE must name the sim_host executable"
#endif
#ifndef ESTIMATOR_NODE_EXE
#error "ESTIMATOR_NODE_EXE must name the estimator_node executable"
#endif

namespace {

namespace fs = std::filesystem;
using est::test::slurp;

int run(const std::string& args, const fs::path& log) {
  const std::string cmd = std::string("'") + SIM_HOST_EXE + "' simulate " + args + " > '" + log.string() + "' 2>&1";
  const int rc = std::system(cmd.c_str());
  return WIFEXITED(rc) ? WEXITSTATUS(rc) : -1;
}

nlohmann::json simulate(const est::test::ScratchDir& dir, const std::string& scenario, const std::string& extra) {
  const fs::path out = dir.path / scenario;
  REQUIRE(run("--scenario " + scenario + " --out '" + out.string() + "' " + extra, dir.path / (scenario + ".log")) ==
          0);
  return nlohmann::json::parse(slurp(out / "metrics.json"));
}

}  // namespace

TEST_CASE("coop-slam: the exercise, sharing z and u against each robot alone", "[simulate]") {
  est::test::ScratchDir dir("sim_team_coop");
  const nlohmann::json m = simulate(dir, "coop-slam", "--seed 1");
  INFO(m.dump(2));
  const fs::path out = dir.path / "coop-slam";
  for (const char* f : {"trajectory.csv", "team_estimates.csv", "trajectory.png", "errors.png",
                        "logs/robot_0.lcmlog", "logs/robot_1.lcmlog", "logs/node_options.txt"})
    CHECK(fs::exists(out / f));
  CHECK(m.at("robots") == 2);
  CHECK(m.at("measurements") == "range only");
  CHECK(m.at("nodes_identical").get<bool>());
  CHECK(m.at("window").at("steps_complete") == m.at("steps"));
  // Seed 1, measured: RMSE 0.09 / 0.11 m shared, 0.17 / 0.23 m alone; NEES 0.86 per dof, 96 % inside the band.
  const nlohmann::json& s = m.at("shared");
  for (const nlohmann::json& r : s.at("per_robot")) CHECK(r.at("position_rmse_m").get<double>() < 0.15);
  CHECK(m.at("sharing_gain").at("ratio").get<double>() < 0.75);
  CHECK(s.at("nees_in_95_band_share").get<double>() > 0.9);
  CHECK(s.at("nees_mean_per_dof").get<double>() > 0.5);
  CHECK(s.at("nees_mean_per_dof").get<double>() < 1.5);
  CHECK(s.at("landmark_error_mean_m").get<double>() < 0.2);
  CHECK(slurp(out / "logs/node_options.txt").find("--team-landmark 100,2,3") != std::string::npos);
}

TEST_CASE("coop-slam-team: four robots map twelve landmarks from scratch with range and bearing", "[simulate]") {
  est::test::ScratchDir dir("sim_team_coop4");
  const nlohmann::json m = simulate(dir, "coop-slam-team", "--seed 3 --duration 30 --no-plots");
  INFO(m.dump(2));
  CHECK(m.at("robots") == 4);
  CHECK(m.at("shared").at("landmarks_mapped") == 12);
  CHECK(m.at("nodes_identical").get<bool>());
  CHECK(m.at("shared").at("landmark_error_mean_m").get<double>() < 0.15);
  CHECK(m.at("shared").at("nees_in_95_band_share").get<double>() > 0.85);
  CHECK(m.at("sharing_gain").at("ratio").get<double>() < 0.8);
  for (const nlohmann::json& r : m.at("shared").at("per_robot")) CHECK(r.at("position_rmse_m").get<double>() < 0.15);
}

TEST_CASE("coop-slam: the same seed writes the same estimates, byte for byte", "[simulate]") {
  est::test::ScratchDir dir("sim_team_coop_repeat");
  simulate(dir, "coop-slam", "--seed 4 --duration 10 --no-plots");
  const std::string first = slurp(dir.path / "coop-slam" / "team_estimates.csv");
  simulate(dir, "coop-slam", "--seed 4 --duration 10 --no-plots");
  CHECK(slurp(dir.path / "coop-slam" / "team_estimates.csv") == first);
  simulate(dir, "coop-slam", "--seed 5 --duration 10 --no-plots");
  CHECK(slurp(dir.path / "coop-slam" / "team_estimates.csv") != first);
}

TEST_CASE("coop-slam-team: the run's one log replays through every robot's team node to the run's estimates, bit for "
          "bit, and holds each robot's truth and estimate", "[simulate][replay]") {
  est::test::ScratchDir dir("sim_team_coop_log");
  const nlohmann::json m = simulate(dir, "coop-slam-team", "--seed 2 --duration 8 --no-plots");
  const fs::path out = dir.path / "coop-slam-team";
  const nlohmann::json sidecar = nlohmann::json::parse(slurp(out / "run.lcmlog.json"));
  INFO(sidecar.dump(2));
  for (int a = 0; a < 4; ++a) {
    const std::string s = std::to_string(a);
    CHECK(sidecar.at("messages").at("EST_TEAM_OWN_" + s) == 80);
    CHECK(sidecar.at("messages").at("EST_GROUND_TRUTH_" + s) == 80);
    CHECK(sidecar.at("messages").at("EST_POSE_" + s) == 80);
  }
  // Each robot's node, replaying the log, writes the lines the run's node 0 wrote (all nodes hold the same estimate).
  const std::string expected = slurp(out / "team_estimates.csv");
  REQUIRE(expected.size() > 1000u);
  const auto& replays = sidecar.at("estimator_node_replays");
  REQUIRE(replays.size() == 4u);
  for (std::size_t a = 0; a < replays.size(); ++a) {
    const fs::path lines = dir.path / ("replay_" + std::to_string(a) + ".csv");
    const std::string cmd = std::string("'") + ESTIMATOR_NODE_EXE + "' " + replays[a].get<std::string>() +
                            " --team-out '" + lines.string() + "' > '" + lines.string() + ".log' 2>&1";
    const int rc = std::system(cmd.c_str());
    REQUIRE((WIFEXITED(rc) && WEXITSTATUS(rc) == 0));
    INFO("robot " << a << ": " << slurp(lines.string() + ".log"));
    CHECK(slurp(lines) == expected);
  }
  // The log's estimates against its truth give the run's RMSE per robot (what sim_host plot reads).
  std::map<std::string, std::vector<est_lcm::pose_estimate_t>> poses;
  std::map<std::string, std::vector<est_lcm::ground_truth_t>> truths;
  ::lcm::LogFile log((out / "run.lcmlog").string(), "r");
  REQUIRE(log.good());
  while (const ::lcm::LogEvent* e = log.readNextEvent()) {
    if (e->channel.rfind("EST_POSE_", 0) == 0) {
      est_lcm::pose_estimate_t p;
      REQUIRE(p.decode(e->data, 0, e->datalen) == e->datalen);
      poses[e->channel.substr(9)].push_back(p);
    } else if (e->channel.rfind("EST_GROUND_TRUTH_", 0) == 0) {
      est_lcm::ground_truth_t g;
      REQUIRE(g.decode(e->data, 0, e->datalen) == e->datalen);
      truths[e->channel.substr(17)].push_back(g);
    }
  }
  for (int a = 0; a < 4; ++a) {
    const auto& p = poses[std::to_string(a)];
    const auto& t = truths[std::to_string(a)];
    REQUIRE(p.size() == t.size());
    double se = 0.0;
    for (std::size_t k = 0; k < p.size(); ++k) {
      CHECK(p[k].stamp_ns == t[k].stamp_ns);
      se += std::pow(std::hypot(static_cast<double>(p[k].x_m - t[k].x_m), static_cast<double>(p[k].y_m - t[k].y_m)), 2);
    }
    CHECK(std::sqrt(se / static_cast<double>(p.size())) ==
          Approx(m.at("shared").at("per_robot").at(static_cast<std::size_t>(a)).at("position_rmse_m").get<double>()).epsilon(1e-4));
  }
}
