#pragma once
// The built-in scenarios: sim_host/scenarios/NAME.toml, embedded into the binary at build time
// (cmake/embed_scenarios.cmake), so an installed or moved sim_host still has them. Host only.
#include <string>
#include <vector>

#include "sim/scenario_file.hpp"

namespace sim {

struct BuiltinScenario {
  std::string name;  // the file's stem: `sim_host run NAME`
  std::string path;  // in the repository, for messages
  std::string text;  // the TOML
};
const std::vector<BuiltinScenario>& builtin_scenarios();  // by name
const BuiltinScenario* find_builtin_scenario(const std::string& name);  // null when none

// NAME of a built-in scenario, else a FILE read from disk, with its --set overrides. Throws ScenarioFileError for a
// malformed scenario or a refused override and std::runtime_error when it is neither a built-in nor a readable file.
ScenarioFile load_scenario(const std::string& name_or_file, const std::vector<ScenarioOverride>& overrides = {});

}  // namespace sim
