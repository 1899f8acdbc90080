#pragma once
// The one runner behind `sim_host run` and `sim_host simulate`: a scenario file's configuration run end to end
// (the single robot through run_simulation, a robot team, or a motion exercise), its files written to a folder and
// its summary printed, with progress on a terminal while it runs. Host only (throws).
#include <cstdint>
#include <string>

#include "sim/live_run.hpp"
#include "sim/scenario_file.hpp"

namespace sim {

struct RunOptions {
  std::string out;     // output directory (created)
  bool plots = true;   // the PNG figures (gnuplot)
  bool quiet = false;  // no progress line, even on a terminal
  // The live view (view/live_view.hpp) on localhost:view_port (0: none; a single robot or a team: every robot's
  // truth and estimate and the landmarks; an exercise has none), the run paced at view_speed times real time (0: as
  // fast as it goes), started once a viewer subscribed with view_wait.
  std::uint16_t view_port = 0;
  double view_speed = 1.0;
  bool view_wait = false;
  // After the lockstep run, the run again live against estimator_node processes (sim/live_run.hpp); empty: none.
  std::string live_lcm_url{};
  LiveOptions live{};
};

void run_scenario(const ScenarioFile& scenario, const RunOptions& options);

}  // namespace sim
