#pragma once
// estimator_node --filter coop-ekf: one robot's node of a team running cooperative EKF-SLAM (node/team_spec.hpp).
// Live, on LCM: the robot's own step messages (its controls and measurements, as its drivers publish them on
// EST_TEAM_OWN_<id>) go into its team window and out on the team channel (EST_TEAM) for the others; the others'
// messages come in from the team channel through the HAL's team validator (hal/team/validator.hpp) into the same
// window. Every closed step advances the team's estimator, writes one line (--team-out) and publishes the node's
// estimate of its own robot on EST_POSE_<id> (pose_estimate_t; a point robot: heading 0). Nodes of a team that
// receive the same messages write the same lines, bit for bit. Replay (--replay LOG, a team run's run.lcmlog): the
// log's EST_TEAM_OWN_<id> as the own messages and every other EST_TEAM_OWN_<b> as the team's, in the log's order,
// as fast as it goes (paced with --view), nothing published. Host only; throws std::invalid_argument on a bad configuration.
#include <cstdint>
#include <cstdio>
#include <memory>
#include <string>

#include "node/team_spec.hpp"

namespace CLI {
class App;
}

namespace node {

struct TeamNodeConfig {
  TeamSpec spec;
  std::int32_t robot_id = 0;
  std::string lcm_url;        // empty: LCM's default (udpm multicast)
  std::string own_channel;    // empty: own_team_channel(robot_id)
  std::string team_channel = "EST_TEAM";
  std::string out_path;       // --team-out: one line per closed step
  std::string counts_path;    // --team-counts: every counter at the end, a "name value" line each
  std::string replay_path;    // --replay: a team run's log instead of live LCM
  double duration_s = 0.0;    // stop after this long (0: no limit)
  double idle_exit_s = 0.0;   // > 0: stop this long after the robot's own messages stopped (the end of a played log)
  double drop_share = 0.0;    // the publisher drops this share of its team messages (a lossy network, reproducibly)
  std::uint32_t silent_from = 0, silent_to = 0;  // steps [from, to] not published: the robot falls silent, rejoins
  std::uint64_t seed = 1;     // of the drops
  bool quiet = false;
  // --view PORT: every robot's truth and estimate, the landmarks and the status (view/foxglove_json.hpp); a replay
  // is then paced by the log's receive times (--replay-speed) and --view-wait holds it until a viewer subscribed.
  std::uint16_t view_port = 0;
  bool view_wait = false;
  double replay_speed = -1.0;
};

std::string own_team_channel(std::int32_t robot_id);
std::string team_pose_channel(std::int32_t robot_id);  // EST_POSE_<id>
std::string team_truth_channel(std::int32_t robot_id);  // EST_GROUND_TRUTH_<id> (a team run's log)

void add_team_node_options(CLI::App& app, TeamNodeConfig& c);
void finish_team_node_options(TeamNodeConfig& c);  // throws CLI::ValidationError

class TeamNode {
 public:
  explicit TeamNode(const TeamNodeConfig& config);
  ~TeamNode();
  TeamNode(const TeamNode&) = delete;
  TeamNode& operator=(const TeamNode&) = delete;

  int run();  // until --duration, --idle-exit after the own stream ends, or SIGINT/SIGTERM; the exit status
  void print_summary(std::FILE* f) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace node
