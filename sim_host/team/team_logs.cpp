#include "team/team_logs.hpp"

#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>

#include "hal/lcm/lcm_convert.hpp"
#include "hal/team/lcm.hpp"
#include "node/lcm_log_io.hpp"
#include "node/team_node.hpp"

namespace sim::team {

namespace {

std::string suffixed(const char* channel, std::size_t a) { return std::string(channel) + "_" + std::to_string(a); }

}  // namespace

void write_team_logs(const std::filesystem::path& dir, const std::string& scenario,
                     const std::vector<std::vector<est::team::TeamMessage>>& by_robot,
                     const std::vector<TeamLogStep>& steps, const node::TeamSpec* spec) {
  std::filesystem::create_directories(dir);
  const std::string log = (dir / "run.lcmlog").string();
  std::map<std::string, std::uint64_t> counts;
  {
    node::LogWriter w(log);
    const auto write = [&](const std::string& channel, hal::TimeNs t, const auto& m) {
      w.write(channel, t, m);
      ++counts[channel];
    };
    for (std::size_t k = 0; k < steps.size(); ++k) {
      const TeamLogStep& s = steps[k];
      for (std::size_t a = 0; a < by_robot.size(); ++a)
        if (k < by_robot[a].size())
          write(node::own_team_channel(static_cast<std::int32_t>(a)), by_robot[a][k].stamp_ns,
                hal::lcm::to_lcm(by_robot[a][k]));
      for (std::size_t a = 0; a < s.truth.size(); ++a) {
        est_lcm::ground_truth_t g{};
        g.stamp_ns = s.stamp_ns;
        g.x_m = s.truth[a].x;
        g.y_m = s.truth[a].y;
        g.theta_rad = s.truth[a].theta;
        write(suffixed("EST_GROUND_TRUTH", a), s.stamp_ns, g);
      }
      for (std::size_t a = 0; a < s.estimate.size(); ++a)
        write(suffixed("EST_POSE", a), s.estimate[a].stamp_ns, hal::lcm::to_lcm(s.estimate[a]));
    }
    if (w.failures() > 0) throw std::runtime_error("writing the LCM log " + log + " failed");
  }
  const std::size_t robots = steps.empty() ? by_robot.size() : steps.front().truth.size();
  nlohmann::ordered_json j;
  j["log"] = log;
  j["scenario"] = scenario;
  j["robots"] = robots;
  j["steps"] = steps.size();
  j["channels"] = {{"inputs", spec != nullptr ? "EST_TEAM_OWN_<a> (team_message_t, robot a's own step messages)"
                                              : "none (no node runs this team)"},
                   {"ground_truth", "EST_GROUND_TRUTH_<a>"},
                   {"estimates", "EST_POSE_<a> (robot a's node's estimate of robot a)"}};
  j["messages"] = counts;
  if (spec != nullptr) {
    const std::string options = node::team_command_line(*spec);
    j["team_node_options"] = options;
    nlohmann::ordered_json replays = nlohmann::ordered_json::array();
    for (std::size_t a = 0; a < robots; ++a)
      replays.push_back("--replay " + log + " " + options + " --robot-id " + std::to_string(a));
    j["estimator_node_replays"] = replays;
    j["note"] = "estimator_node with estimator_node_replays[a] takes EST_TEAM_OWN_a as its own robot's messages and "
                "the other EST_TEAM_OWN_b as the team's; its --team-out lines are the run's team_estimates.csv, bit "
                "for bit";
  }
  std::ofstream(log + ".json") << j.dump(2) << "\n";

  if (spec == nullptr) return;
  const std::filesystem::path logs = dir / "logs";
  std::filesystem::create_directories(logs);
  for (std::size_t a = 0; a < by_robot.size(); ++a) {
    node::LogWriter w((logs / ("robot_" + std::to_string(a) + ".lcmlog")).string());
    const std::string channel = node::own_team_channel(static_cast<std::int32_t>(a));
    for (const est::team::TeamMessage& m : by_robot[a]) w.write(channel, m.stamp_ns, hal::lcm::to_lcm(m));
    if (w.failures() > 0) throw std::runtime_error("writing " + (logs / ("robot_" + std::to_string(a))).string() + " failed");
  }
  std::ofstream f(logs / "node_options.txt");
  f << node::team_command_line(*spec) << "\n";
  if (!f) throw std::runtime_error("cannot write " + (logs / "node_options.txt").string());
}

}  // namespace sim::team
