#pragma once
// The robot-team scenarios of `sim_host simulate --scenario NAME`: the cooperative EKF-SLAM exercise (coop-slam),
// a larger team (coop-slam-team), and the three differential-drive robots that resolve which robot they see
// (diffdrive-landmarks). Each writes OUT/metrics.json, OUT/trajectory.csv and figures, and prints a summary.
// Host only (may throw).
#include <cstdint>
#include <string>
#include <vector>

namespace view {
class LiveView;
}

namespace sim::team {

struct TeamRunOptions {
  std::string scenario;      // one of team_scenarios()
  std::string out;           // output directory (created)
  std::uint64_t seed = 1;
  double duration_s = -1.0;  // negative: the scenario's own length
  bool plots = true;
  bool quiet = false;        // no progress line on a terminal
  // Watched live (the view opened with the scenario's robots, TeamScenarioInfo::robots): at every step each robot's
  // truth and estimate (node::feed_team's channels: /robot<a>/truth, /robot<a>/estimate and its ellipse, /status)
  // and the landmarks (mapped, or the known ones), the run paced at view_speed times real time (0: as fast as it
  // goes). The outputs are the same bits as an unwatched run's. Null: unwatched.
  view::LiveView* view = nullptr;
  double view_speed = 1.0;
};

struct TeamScenarioInfo {
  std::string name;
  std::string what;
  int robots = 0;
};
const std::vector<TeamScenarioInfo>& team_scenarios();
bool is_team_scenario(const std::string& name);
const TeamScenarioInfo& team_scenario(const std::string& name);  // throws std::runtime_error for an unknown name

// Runs the scenario end to end; throws std::runtime_error on bad options or unwritable output.
void run_team_scenario(const TeamRunOptions& o);

// The scenarios' own entry points (coop_slam.cpp, diffdrive_landmarks.cpp).
void run_coop_slam(const TeamRunOptions& o, bool team_of_four);
void run_diffdrive_landmarks(const TeamRunOptions& o);

}  // namespace sim::team
