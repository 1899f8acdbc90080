#pragma once
// A campaign: one scenario run for each seed of a range (with the same --set overrides), one `sim_host run` per seed
// into DIR/seed-N; or, when a --set gives several values (KEY=V1,V2,V3), for each combination of the values of every
// such key (the cartesian product, the first key varying slowest) and each seed, into DIR/<combination>/seed-N.
// campaign.json in DIR describes it, so `sim_host aggregate DIR` needs nothing else; the local sweep (sweep.hpp) and
// the Slurm job array (slurm.hpp) run the same command line. Host only (throws).
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace sim::campaign {

// A key of the parameter grid and its values (TOML values, as `sim_host run --set KEY=VALUE` takes them).
struct GridAxis {
  std::string key;
  std::vector<std::string> values;
};

// One point of the grid: its index, the KEY=VALUE of each axis, and its folder's name ("" without a grid: the seeds'
// folders are then the campaign's own, DIR/seed-N, as before grids).
struct Combination {
  std::size_t index = 0;
  std::vector<std::string> sets;
  std::string name;
};

struct Campaign {
  std::string scenario;            // a built-in NAME or an absolute FILE path
  std::uint64_t first_seed = 1;    // seeds first_seed..last_seed, both included
  std::uint64_t last_seed = 1;
  std::vector<std::string> sets;   // KEY=VALUE for every run, as `sim_host run --set`
  std::vector<GridAxis> grid;      // the keys given several values; empty: no grid
  double duration_s = 0.0;         // > 0: `sim_host run --duration`
  std::string sim_host;            // absolute path of the sim_host that runs each seed
  std::size_t seed_count() const { return static_cast<std::size_t>(last_seed - first_seed + 1); }
  // Every combination of the grid's values (one, unnamed, without a grid); the first axis varies slowest.
  std::vector<Combination> combinations() const;
  std::size_t run_count() const { return combinations().size() * seed_count(); }
};

// A sweep's `--set KEY=VALUE` (one value: into `sets`) or `--set KEY=V1,V2,...` (several: a grid axis). Values are
// split at the commas outside brackets, braces and quotes, so a TOML array or string keeps its commas. A key given
// twice where one is a grid axis is refused (std::invalid_argument).
void add_set(Campaign& c, const std::string& key_equals_values);
// The values of `text` split as add_set splits them.
std::vector<std::string> split_values(const std::string& text);

// "A..B" (or "N": one seed) into the campaign's range; std::invalid_argument with the reason otherwise.
void parse_seed_range(const std::string& text, Campaign& c);

// DIR/seed-N: where seed N's run writes (metrics.json, run.log: its stdout and stderr, exit_status: its exit code).
std::filesystem::path seed_dir(const std::filesystem::path& dir, std::uint64_t seed);
// A combination's folder: DIR/<name>, or DIR itself without a grid.
std::filesystem::path combination_dir(const std::filesystem::path& dir, const Combination& k);

// What `sim_host run` takes after SCENARIO --seed N --out DIR/seed-N: --quiet --no-plots [--duration S] [--set ...]
// (the campaign's fixed sets; the grid's are the combination's, combination_options()).
std::vector<std::string> run_options(const Campaign& c);
// --set KEY=VALUE for each axis of a combination.
std::vector<std::string> combination_options(const Combination& k);
// The whole command of one seed of one combination (no shell).
std::vector<std::string> seed_command(const Campaign& c, const Combination& k, std::uint64_t seed,
                                      const std::filesystem::path& dir);

// DIR/campaign.json: written before a campaign runs, read by the aggregation.
void write_campaign_json(const Campaign& c, const std::filesystem::path& dir);
Campaign read_campaign_json(const std::filesystem::path& dir);

}  // namespace sim::campaign
