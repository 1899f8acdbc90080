#include "team/team_logs.hpp"

#include <fstream>
#include <lcm/lcm-cpp.hpp>
#include <stdexcept>
#include <string>

#include "hal/team/lcm.hpp"
#include "node/team_node.hpp"

namespace sim::team {

void write_team_logs(const std::filesystem::path& dir, const CoopWorld& /*w*/,
                     const std::vector<std::vector<est::team::TeamMessage>>& by_robot, const node::TeamSpec& spec) {
  const std::filesystem::path logs = dir / "logs";
  std::filesystem::create_directories(logs);
  std::vector<std::uint8_t> buffer;
  for (std::size_t a = 0; a < by_robot.size(); ++a) {
    const std::string path = (logs / ("robot_" + std::to_string(a) + ".lcmlog")).string();
    ::lcm::LogFile file(path, "w");
    if (!file.good()) throw std::runtime_error("cannot create the LCM log " + path);
    const std::string channel = node::own_team_channel(static_cast<std::int32_t>(a));
    for (const est::team::TeamMessage& m : by_robot[a]) {
      const est_lcm::team_message_t msg = hal::lcm::to_lcm(m);
      const int n = msg.getEncodedSize();
      buffer.resize(static_cast<std::size_t>(n));
      if (msg.encode(buffer.data(), 0, n) != n) throw std::runtime_error("LCM encoding failed on " + channel);
      ::lcm::LogEvent e;
      e.eventnum = 0;
      e.timestamp = m.stamp_ns / 1000;
      e.channel = channel;
      e.datalen = n;
      e.data = buffer.data();
      if (file.writeEvent(&e) != 0) throw std::runtime_error("writing " + path + " failed");
    }
  }
  std::ofstream f(logs / "node_options.txt");
  f << node::team_command_line(spec) << "\n";
  if (!f) throw std::runtime_error("cannot write " + (logs / "node_options.txt").string());
}

}  // namespace sim::team
