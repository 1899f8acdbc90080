#pragma once
// The robot-team scenarios of `sim_host simulate --scenario NAME`: the cooperative EKF-SLAM exercise (coop-slam),
// a larger team (coop-slam-team), and the three differential-drive robots that resolve which robot they see
// (diffdrive-landmarks). Each writes OUT/metrics.json, OUT/trajectory.csv and figures, and prints a summary.
// Host only (may throw).
#include <cstdint>
#include <string>
#include <vector>

namespace sim::team {

struct TeamRunOptions {
  std::string scenario;      // one of team_scenarios()
  std::string out;           // output directory (created)
  std::uint64_t seed = 1;
  double duration_s = -1.0;  // negative: the scenario's own length
  bool plots = true;
  bool quiet = false;        // no progress line on a terminal
};

struct TeamScenarioInfo {
  std::string name;
  std::string what;
};
const std::vector<TeamScenarioInfo>& team_scenarios();
bool is_team_scenario(const std::string& name);

// Runs the scenario end to end; throws std::runtime_error on bad options or unwritable output.
void run_team_scenario(const TeamRunOptions& o);

// The scenarios' own entry points (coop_slam.cpp, diffdrive_landmarks.cpp).
void run_coop_slam(const TeamRunOptions& o, bool team_of_four);
void run_diffdrive_landmarks(const TeamRunOptions& o);

}  // namespace sim::team
