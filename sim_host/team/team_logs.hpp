#pragma once
// What a team scenario leaves for estimator_node --filter coop-ekf and the network test: OUT/logs/robot_<a>.lcmlog
// (robot a's own step messages on channel EST_TEAM_OWN_<a>, at their step times, as its drivers would publish
// them) and OUT/logs/node_options.txt (the options every node of the team runs with). Host only.
#include <filesystem>
#include <vector>

#include "est/team/team_message.hpp"
#include "node/team_spec.hpp"
#include "team/coop_world.hpp"

namespace sim::team {

void write_team_logs(const std::filesystem::path& dir, const CoopWorld& w,
                     const std::vector<std::vector<est::team::TeamMessage>>& by_robot, const node::TeamSpec& spec);

}  // namespace sim::team
