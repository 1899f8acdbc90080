#pragma once
// The team estimator of `estimator_node --filter coop-ekf` and of the simulator's team scenarios, in one place: the
// host's capacities, what every robot's node must agree on (the team, its initial estimate, the noise, the window),
// the command line that gives it, and the line each closed step writes (so a node's output and the in-process
// lockstep run compare bit for bit). Host only.
#include <cstdint>
#include <string>
#include <vector>

#include "est/team/coop_ekf_estimator.hpp"
#include "est/team/team_window.hpp"

namespace CLI {  // <CLI/CLI.hpp> costs ~8 s of compile per file: only the files that register options include it
class App;
}  // namespace CLI

namespace node {

inline constexpr int kTeamMaxRobots = 8;      // R on the host
inline constexpr int kTeamMaxLandmarks = 64;  // M on the host
inline constexpr int kTeamWindowSteps = 16;   // the reorder window's capacity, steps
using TeamEstimator = est::team::CoopEkfEstimator<kTeamMaxRobots, kTeamMaxLandmarks>;
using TeamWindow = est::team::TeamWindow<kTeamMaxRobots, kTeamWindowSteps>;

struct TeamLandmarkPrior {
  std::int32_t id = 0;
  float x = 0.0f, y = 0.0f;
};

struct TeamSpec {
  est::team::CoopEkfConfig estimator;       // robots, step, noise
  std::vector<float> initial;               // x0,y0,x1,y1,...: the team's initial estimate
  float initial_sigma_m = 0.2f;             // per axis, every robot
  std::vector<TeamLandmarkPrior> landmarks; // landmarks with a prior (the exercise's one)
  float landmark_sigma_m = 0.3f;
  int window_steps = 10;                    // steps a missing message is waited for (<= kTeamWindowSteps)
  std::uint32_t first_seq = 1;
};

// Registers --team-size, --team-step, --team-initial, ... on `app` (group "Team (--filter coop-ekf)").
void add_team_spec_options(CLI::App& app, TeamSpec& s);
// Throws std::invalid_argument for an inconsistent spec (initial estimate of the wrong size, window too large...).
void check_team_spec(const TeamSpec& s);
// The options that give `s`.
std::string team_command_line(const TeamSpec& s);

// A window and estimator started from the spec (throws std::invalid_argument if the firmware refuses it).
void start_team(const TeamSpec& s, TeamWindow& w, TeamEstimator& e);

// One line per closed step: seq, status (hex), dim, then every mean entry and a digest of the active covariance,
// floats as hex (%a) so that two runs compare exactly. The header names the columns.
std::string team_estimate_header();
std::string team_estimate_line(std::uint32_t seq, const TeamEstimator& e);

}  // namespace node
