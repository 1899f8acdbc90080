#pragma once
// The local sweep: each seed of a campaign (campaign.hpp), of each combination of its grid, run as its own
// `sim_host run` process, `jobs` at a time (posix_spawn), its stdout and stderr in [COMBINATION/]seed-N/run.log and
// its exit code in [COMBINATION/]seed-N/exit_status; progress
// (done / total, failures, ETA) on a terminal, nothing off one. Host only (throws).
#include <cstddef>
#include <filesystem>

#include "campaign/campaign.hpp"

namespace sim::campaign {

struct SweepCounts {
  std::size_t done = 0;
  std::size_t failed = 0;
};

SweepCounts run_sweep(const Campaign& c, const std::filesystem::path& dir, std::size_t jobs, bool quiet);

}  // namespace sim::campaign
