#pragma once
// A scenario file (TOML, read with toml++): what `sim_host run` runs. One of three runners: a single robot through
// the HAL and the filter loop (what `sim_host simulate` runs: ScenarioConfig + FilterOptions, from which
// estimator_spec() makes the estimator's node::EstimatorSpec), a robot team (team/team_scenarios.hpp), or a motion
// exercise (sample-motion). sim_host/scenarios/example.toml documents every key with its unit, default and meaning;
// a key left out takes simulate's default. Host only (throws).
#include <cstdint>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

#include "sim/scenario.hpp"
#include "sim/simulate.hpp"

namespace sim {

enum class ScenarioRunner { simulate, team, exercise };

struct ScenarioFile {
  std::string source;       // the file it was read from (or the built-in's repository path)
  std::string description;  // one line, for `sim_host list`
  ScenarioRunner runner = ScenarioRunner::simulate;
  // simulate
  ScenarioConfig scenario;
  FilterOptions filter;
  // team: one of team::team_scenarios(), with scenario.seed and team_duration_s (negative: the team's own length)
  std::string team;
  double team_duration_s = -1.0;
  // exercise: sample-motion's bicycle-exercise, its seed and samples per case
  std::string exercise;
  std::uint64_t exercise_seed = 0;
  int exercise_samples = 5000;
};

// A refused file: what() is "FILE:LINE:COLUMN: reason" (nothing runs).
class ScenarioFileError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// One `--set KEY=VALUE`: a key by its dotted path in the file ("filter.particles", "faults.counts.scan.stale") and
// a TOML value (256, 0.5, true, "ekf"; a bare word is taken as a string: filter.type=ekf).
struct ScenarioOverride {
  std::string key;
  std::string value;
};
// Splits "KEY=VALUE"; ScenarioFileError ("--set TEXT: ...") when there is no '=' or no key.
ScenarioOverride parse_override(const std::string& key_equals_value);

// Parses `text` as the scenario file `source` (the name errors give; relative map paths are taken from its folder),
// with `overrides` put in place of (or beside) the file's keys before it is read. Throws ScenarioFileError on
// malformed TOML, an unknown key, a value of the wrong type or out of range, or keys that contradict each other
// (e.g. --handlebar on a robot that is not the bicycle); an override's refusal is "--set KEY=VALUE: reason" (a key
// this runner does not read, a value that is not TOML, or any refusal of the value itself).
ScenarioFile parse_scenario(const std::string& text, const std::string& source,
                            const std::vector<ScenarioOverride>& overrides = {});
// Reads and parses a file from disk; ScenarioFileError also when it cannot be read.
ScenarioFile read_scenario_file(const std::string& path, const std::vector<ScenarioOverride>& overrides = {});

// `--duration S` of sim_host run and sweep: the run's length in place of the file's; ScenarioFileError
// ("--duration: reason") outside (0, 3600] s or for an exercise, which has no duration.
void set_duration(ScenarioFile& f, double duration_s);

// Every key the parser knows, as dotted paths ("sensors.rangefinder.hz"), over all three runners or of one.
std::set<std::string> scenario_file_keys();
std::set<std::string> scenario_file_keys(ScenarioRunner runner);

}  // namespace sim
