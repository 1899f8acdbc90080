#include "team/team_scenarios.hpp"

#include <stdexcept>

namespace sim::team {

const std::vector<TeamScenarioInfo>& team_scenarios() {
  static const std::vector<TeamScenarioInfo> k = {
      {"coop-slam",
       "the cooperative EKF-SLAM exercise: two holonomic point robots and one landmark, range only, shared z and u", 2},
      {"coop-slam-team", "cooperative EKF-SLAM of four point robots and twelve landmarks, range and bearing", 4},
      {"diffdrive-landmarks",
       "three differential-drive robots, known landmarks, anonymous robot sightings resolved over the 3! "
       "assignments, global localization", 3},
  };
  return k;
}

bool is_team_scenario(const std::string& name) {
  for (const TeamScenarioInfo& s : team_scenarios())
    if (s.name == name) return true;
  return false;
}

const TeamScenarioInfo& team_scenario(const std::string& name) {
  for (const TeamScenarioInfo& s : team_scenarios())
    if (s.name == name) return s;
  throw std::runtime_error("unknown team scenario '" + name + "'");
}

void run_team_scenario(const TeamRunOptions& o) {
  if (o.scenario == "coop-slam") return run_coop_slam(o, false);
  if (o.scenario == "coop-slam-team") return run_coop_slam(o, true);
  if (o.scenario == "diffdrive-landmarks") return run_diffdrive_landmarks(o);
  throw std::runtime_error("unknown team scenario '" + o.scenario + "'");
}

}  // namespace sim::team
