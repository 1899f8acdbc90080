#pragma once
// A campaign (campaign.hpp) as a Slurm job array: DIR/campaign.sbatch, one array task per seed (--array=A-B, the
// seed is $SLURM_ARRAY_TASK_ID), each running the local sweep's command for its seed into DIR/seed-N with its
// run.log and exit_status, so `sim_host aggregate DIR` reads the folder as it reads a local sweep's. With a parameter
// grid, one task per run (--array=0-(combinations x seeds - 1)), into DIR/<combination>/seed-N. Slurm's MaxArraySize
// (1001 by default) bounds the tasks. Host only (throws).
#include <filesystem>
#include <string>

#include "campaign/campaign.hpp"

namespace sim::campaign {

// The batch script's text for a campaign in `dir` (an absolute path).
std::string slurm_batch_script(const Campaign& c, const std::filesystem::path& dir);

// Writes DIR/campaign.json and DIR/campaign.sbatch (executable); runs nothing.
void emit_slurm(const Campaign& c, const std::filesystem::path& dir);

}  // namespace sim::campaign
