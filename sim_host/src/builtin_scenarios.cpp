#include "sim/builtin_scenarios.hpp"

#include <algorithm>
#include <filesystem>
#include <stdexcept>

namespace sim {

const std::vector<BuiltinScenario>& builtin_scenarios() {
  static const std::vector<BuiltinScenario> k = [] {
    std::vector<BuiltinScenario> v = {
#include "sim/builtin_scenarios.inc"
    };
    std::sort(v.begin(), v.end(), [](const BuiltinScenario& a, const BuiltinScenario& b) { return a.name < b.name; });
    return v;
  }();
  return k;
}

const BuiltinScenario* find_builtin_scenario(const std::string& name) {
  for (const BuiltinScenario& s : builtin_scenarios())
    if (s.name == name) return &s;
  return nullptr;
}

ScenarioFile load_scenario(const std::string& name_or_file, const std::vector<ScenarioOverride>& overrides) {
  if (const BuiltinScenario* b = find_builtin_scenario(name_or_file)) return parse_scenario(b->text, b->path, overrides);
  if (std::filesystem::is_regular_file(name_or_file)) return read_scenario_file(name_or_file, overrides);
  throw std::runtime_error("'" + name_or_file + "' is neither a built-in scenario (sim_host list) nor a file");
}

}  // namespace sim
