#pragma once
// The sim_host subcommands: each file under sim_host/src/ that implements one adds it to the CLI here.
namespace CLI {
class App;
}

namespace sim {

// sample-motion: posterior samples of the motion models (sim_host/src/sample_motion_command.cpp).
void add_sample_motion_command(CLI::App& app);

// simulate: the host simulation end to end; record: its sensor stream as an LCM log (src/simulate_command.cpp).
void add_simulate_command(CLI::App& app);
void add_record_command(CLI::App& app);

// run: a scenario file, built in or from disk; list: the built-in scenarios (src/run_command.cpp).
void add_run_command(CLI::App& app);
void add_list_command(CLI::App& app);

// sweep: a scenario over many seeds, here or as a Slurm job array; aggregate: a campaign's folder
// (src/campaign_command.cpp).
void add_sweep_command(CLI::App& app);
void add_aggregate_command(CLI::App& app);

// learn-beam-model: EM for the beam model's intrinsic parameters from a recorded log (src/learn_beam_model_command.cpp).
void add_learn_beam_model_command(CLI::App& app);

}  // namespace sim
