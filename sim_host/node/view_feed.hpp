#pragma once
// What a live view (view/live_view.hpp) is fed from an estimator pipeline: its estimates, its map and its particle
// cloud, in the view's types. estimator_node and sim_host's runs share it. Host only.
#include <cstdint>
#include <memory>
#include <string>

#include "hal/estimate.hpp"
#include "node/estimator_pipeline.hpp"
#include "node/team_spec.hpp"
#include "view/live_view.hpp"

namespace CLI {
class App;
}

namespace node {

// --view PORT (`what`: what it shows), --view-wait and --replay-speed, for estimator_node and its team node.
// speed stays < 0 when not given: finish with replay_speed_default().
void add_view_options(CLI::App& app, std::uint16_t& port, bool& wait, double& speed, const std::string& what);
inline double replay_speed_default(double speed, std::uint16_t port) {
  return speed >= 0.0 ? speed : (port != 0 ? 1.0 : 0.0);
}
// --view-wait: returns once a viewer has subscribed, or stopped() says so.
void wait_for_viewer(const view::LiveView& v, bool (*stopped)());
// The live view of `program` on localhost:port (team_robots > 0: a team's channels; the server's name is the
// program's first word), its address said on stderr as "PROGRAM: live view on http://localhost:PORT/ (Foxglove:
// ws://localhost:PORT)" (what the view tests wait for).
// Throws std::runtime_error when the port cannot be served.
std::unique_ptr<view::LiveView> open_view(std::uint16_t port, const std::string& program, int team_robots = 0);
// "port=P clients=C pages=G sent=S dropped_handoff=H dropped_slow=D": a run's summary line of its view.
std::string view_counters_line(const view::LiveView& v);

view::EstimateSample view_sample(const hal::Estimate& e);
view::MapGrid view_map(const est::OccupancyGrid& g);
// The pipeline's particles (MCL), when the view wants a cloud (its rate, a subscriber).
void feed_particles(view::LiveView& v, const EstimatorPipeline& p, hal::TimeNs stamp_ns);

// A team's estimate after a closed step (estimator_node --filter coop-ekf): every robot's position with its 2-sigma
// ellipse (the own robot's with the status), and the mapped landmarks at the view's rate.
void feed_team(view::LiveView& v, const TeamEstimator& e, std::int32_t own_robot, hal::TimeNs stamp_ns);

}  // namespace node
