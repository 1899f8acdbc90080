#pragma once
// A campaign: one scenario run for each seed of a range (with the same --set overrides), one `sim_host run` per seed
// into DIR/seed-N. campaign.json in DIR describes it, so `sim_host aggregate DIR` needs nothing else; the local sweep
// (sweep.hpp) and the Slurm job array (slurm.hpp) run the same command line. Host only (throws).
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace sim::campaign {

struct Campaign {
  std::string scenario;            // a built-in NAME or an absolute FILE path
  std::uint64_t first_seed = 1;    // seeds first_seed..last_seed, both included
  std::uint64_t last_seed = 1;
  std::vector<std::string> sets;   // KEY=VALUE, as `sim_host run --set`
  double duration_s = 0.0;         // > 0: `sim_host run --duration`
  std::string sim_host;            // absolute path of the sim_host that runs each seed
  std::size_t seed_count() const { return static_cast<std::size_t>(last_seed - first_seed + 1); }
};

// "A..B" (or "N": one seed) into the campaign's range; std::invalid_argument with the reason otherwise.
void parse_seed_range(const std::string& text, Campaign& c);

// DIR/seed-N: where seed N's run writes (metrics.json, run.log: its stdout and stderr, exit_status: its exit code).
std::filesystem::path seed_dir(const std::filesystem::path& dir, std::uint64_t seed);

// What `sim_host run` takes after SCENARIO --seed N --out DIR/seed-N: --quiet --no-plots [--duration S] [--set ...].
std::vector<std::string> run_options(const Campaign& c);
// The whole command of one seed (no shell).
std::vector<std::string> seed_command(const Campaign& c, std::uint64_t seed, const std::filesystem::path& dir);

// DIR/campaign.json: written before a campaign runs, read by the aggregation.
void write_campaign_json(const Campaign& c, const std::filesystem::path& dir);
Campaign read_campaign_json(const std::filesystem::path& dir);

}  // namespace sim::campaign
