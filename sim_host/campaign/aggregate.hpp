#pragma once
// The aggregation of a campaign's folder (campaign.hpp): each seed's result read from DIR/seed-N, every metric of
// the runs' metrics.json summarized over the seeds (statistics.hpp), the failed seeds listed with their exit status,
// reason and log; written to DIR/aggregate.json and drawn in DIR/aggregate.png. `sim_host sweep` calls it after its
// runs, `sim_host aggregate DIR` on a folder a scheduler filled. Host only (throws).
#include <cstdint>
#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <string>

namespace sim::campaign {

// One seed's outcome: ok when it exited 0 and left a readable metrics.json.
struct SeedResult {
  std::uint64_t seed = 0;
  bool ok = false;
  int exit_status = -1;              // -1: no exit_status file (the run never finished, or never started)
  std::string reason;                // why it failed
  std::filesystem::path log;         // DIR/seed-N/run.log
  std::map<std::string, double> metrics;
};

// The numbers of a run's metrics.json by dotted path ("accuracy.rmse_position_m", "robots.1.position_rmse_m",
// "phases.kidnap_recovery.time_to_localize_s"); booleans as 0/1 (their names added to `booleans`), null left out, and so is -1 where
// metrics.json uses it for "none" (an RMSE, error, time_to_* or *_at_s of a run that never localized).
// Left out: the run's configuration (scenario, filter, seed) and its wall-clock timing, which no two runs share.
std::map<std::string, double> flatten_metrics(const nlohmann::json& metrics, std::set<std::string>* booleans = nullptr);

SeedResult read_seed_result(const std::filesystem::path& dir, std::uint64_t seed, std::set<std::string>* booleans);

// Aggregates DIR (its campaign.json names the seeds); writes DIR/aggregate.json and, with `plot`, DIR/aggregate.png.
// Returns what aggregate.json holds.
nlohmann::ordered_json aggregate_campaign(const std::filesystem::path& dir, bool plot);

// A few lines for the terminal: seeds run and failed (each with its log), the headline metrics.
std::string aggregate_summary(const nlohmann::ordered_json& aggregate);

}  // namespace sim::campaign
