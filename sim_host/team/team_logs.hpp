#pragma once
// What a team scenario leaves for a replay, the plots and estimator_node --filter coop-ekf:
// - OUT/run.lcmlog, the run as one LCM log: every robot's inputs on its own channel as the team node consumes them
//   (EST_TEAM_OWN_<a>, team_message_t; none for a team no node runs), its ground truth (EST_GROUND_TRUTH_<a>) and its
//   estimate (EST_POSE_<a>) at every step, in step order; with the sidecar OUT/run.lcmlog.json (the channels, the
//   message counts and the node options of each robot's replay). `sim_host plot` draws every robot from it.
// - OUT/logs/robot_<a>.lcmlog (robot a's own step messages alone, for lcm-logplayer into its node) and
//   OUT/logs/node_options.txt (the options every node of the team runs with).
// Host only (throws std::runtime_error on an unwritable file).
#include <filesystem>
#include <string>
#include <vector>

#include "est/geometry/pose2.hpp"
#include "est/team/team_message.hpp"
#include "hal/estimate.hpp"
#include "node/team_spec.hpp"

namespace sim::team {

// Every robot's truth and estimate at one step (indexed by robot).
struct TeamLogStep {
  hal::TimeNs stamp_ns = 0;
  std::vector<est::Pose2> truth;
  std::vector<hal::Estimate> estimate;
};

// `by_robot` (robot a's messages, one per step, may be empty) and `steps` in step order; `spec` (may be null: no
// node runs this team) gives the node options of the sidecar and of logs/.
void write_team_logs(const std::filesystem::path& dir, const std::string& scenario,
                     const std::vector<std::vector<est::team::TeamMessage>>& by_robot,
                     const std::vector<TeamLogStep>& steps, const node::TeamSpec* spec);

}  // namespace sim::team
