#pragma once
// `sim_host run SCENARIO --live --lcm URL`: the run again in real time against estimator_node processes, after its
// lockstep run. One node per robot (the options of the run's sidecar, live on the URL instead of --replay), the
// sensor streams of the run's log published on the URL paced at their arrival times (node/pacer.hpp), the nodes'
// estimates (EST_POSE, EST_POSE_<a> for a team) collected from LCM and scored with the lockstep run's metrics against
// the same truth, printed beside the lockstep figures; the nodes are stopped at the end (SIGINT) and their exit
// status and summaries reported. OUT/live/: each node's summary, the estimates it published (live.lcmlog) and
// live.json with both runs' figures. Host only (throws std::runtime_error when a node cannot be started).
//
// With a CAN interface (`--live --can IFACE --lcm URL`, a single robot): the node reads its sensors from the bus
// (estimator_node --can IFACE --lcm URL), can_player sends the run's streams onto it as estimator.dbc frames, each
// message at CLOCK_MONOTONIC stamp + an offset chosen here (so the node's receive stamps map back onto the run's
// time), landmark sightings (no frame) go on LCM stamped on the same clock, and the estimates come back on LCM. The
// bus carries other bits than the lockstep stream (16-bit counters, 1 mm ranges, receive times), so the live
// estimates are paired with the lockstep's by the input they came from and compared within a bound; the node's
// recorded inputs (OUT/live/inputs.lcmlog) replayed in lockstep must give its live estimates bit for bit.
#include <string>

#include "sim/scenario_file.hpp"
#include "sim/simulate.hpp"

namespace sim {

struct LiveOptions {
  std::string lcm_url;        // where the streams go and the estimates come back (udpm://...?ttl=0 for this host)
  std::string node_exe;       // empty: estimator_node beside this executable
  double start_timeout_s = 30.0;  // for a node to say it runs
  double drain_s = 0.5;       // after the last input: the reorder window and the last estimates
  std::string can_interface;  // non-empty: the sensor streams as CAN frames on this interface (a single robot)
  std::string can_player_exe; // empty: can_player beside this executable
  std::string node_args;      // options for every node, in place of the sidecar's options of the same names
};

// What the live run measured, for the caller and the tests.
struct LiveResult {
  int node_exit = -1;         // worst exit status of the nodes (-1: killed)
  std::size_t inputs_published = 0, estimates = 0, matched = 0, identical = 0;
  bool inputs_all_accounted = false;  // every input published reached a node: accepted or counted as rejected
  // Over CAN: live estimates equal to the lockstep replay of the node's recorded inputs (of `estimates`).
  std::size_t replay_identical = 0;
};

// A single robot: `lockstep` is the run just made, its log and sidecar in `out`.
LiveResult run_live_robot(const SimResult& lockstep, const ScenarioConfig& scenario, const FilterOptions& filter,
                          const std::string& out, const LiveOptions& options);

// The same over CAN (options.can_interface); run_live_robot calls it when an interface is given.
LiveResult run_live_robot_can(const SimResult& lockstep, const ScenarioConfig& scenario, const FilterOptions& filter,
                              const std::string& out, const LiveOptions& options);

// A team (the log and sidecar of write_team_logs in `out`): one team node per robot.
LiveResult run_live_team(const std::string& out, const LiveOptions& options);

}  // namespace sim
