#pragma once
// The one runner behind `sim_host run` and `sim_host simulate`: a scenario file's configuration run end to end
// (the single robot through run_simulation, a robot team, or a motion exercise), its files written to a folder and
// its summary printed, with progress on a terminal while it runs. Host only (throws).
#include <string>

#include "sim/scenario_file.hpp"

namespace sim {

struct RunOptions {
  std::string out;     // output directory (created)
  bool plots = true;   // the PNG figures (gnuplot)
  bool quiet = false;  // no progress line, even on a terminal
};

void run_scenario(const ScenarioFile& scenario, const RunOptions& options);

}  // namespace sim
